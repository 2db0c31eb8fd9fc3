// The flight modes the robots' autopilots reported over the radio: the MAVLink HEARTBEATs in the
// UDP datagrams each robot sent, read from medium.pcap as sitlnet writes it
// (tapbridge/pcap_writer.cc). Read by the view, never by the run: the run's threads do no work
// for it. Only a robot whose autopilot sends its MAVLink over the medium (to a ground station on
// another robot) has a mode here; one talking to a GCS on its own loopback has none.
#ifndef SITLNET_VIEW_AIR_MODES_H_
#define SITLNET_VIEW_AIR_MODES_H_

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/common.h"

namespace sitlnet::view {

// A robot's autopilot reported a mode other than its last one.
struct ModeChange {
  TimeNs time_ns = 0;  // Simulated start of the frame's transmission (radiotap TSFT, 1 us).
  int robot = 0;       // Its transmitter (the 802.11 address 2, common's RobotMac).
  std::string mode;    // view/autopilot_mode.h
};

// Reads medium.pcap's bytes in order, in pieces of any size (a file still being written), and
// keeps each robot's mode changes. A first transmission of a DATA frame from robot
// 0..robots-1 carrying an unfragmented IPv4 UDP datagram is searched for MAVLink 2 HEARTBEATs
// (CRC checked) of PX4 or ArduPilot. Retransmissions repeat what was sent and are not read.
// MAVLink 1 frames are not read (PX4 switches to MAVLink 2 once its ground station speaks it).
class AirModeReader {
 public:
  explicit AirModeReader(int robots);
  void Push(const uint8_t* data, size_t size);
  // Throws Error when the bytes read so far are not a pcap file as sitlnet writes it.
  const std::vector<ModeChange>& changes() const { return changes_; }
  // The latest change per robot (by index), or nullptr where none came.
  const ModeChange* Latest(int robot) const;

 private:
  void Record(const uint8_t* record, size_t size);
  void Datagram(TimeNs time_ns, int robot, const uint8_t* data, size_t size);

  int robots_;
  std::vector<uint8_t> pending_;  // Bytes not yet part of a whole record.
  bool header_read_ = false;
  std::vector<ModeChange> changes_;
  std::vector<int> latest_;  // Index into changes_ per robot; -1: none.
};

// Every mode change of `pcap_path` (missing file: none), in time order (stable). Throws Error
// naming the file.
std::vector<ModeChange> ReadAirModes(const std::string& pcap_path, int robots);

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_AIR_MODES_H_
