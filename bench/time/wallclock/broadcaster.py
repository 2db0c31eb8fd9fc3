#!/usr/bin/python3
"""A wall-clock robot for bench/time: a 64-byte UDP broadcast on wlan0 every 0.1 s of its own
clock (time.sleep, which libfaketime dilates), until killed."""
import socket
import time

sender = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
sender.setsockopt(socket.SOL_SOCKET, socket.SO_BROADCAST, 1)
sender.setsockopt(socket.SOL_SOCKET, socket.SO_BINDTODEVICE, b"wlan0")
payload = bytes(64)
while True:
    sender.sendto(payload, ("255.255.255.255", 47100))
    time.sleep(0.1)
