// gcs_relay: runs in a ground station node and joins the vehicles' MAVLink on the simulated
// radio to a GCS on the host, both ways, through Unix datagram sockets in a host folder (no route
// between any namespace and the host; docs/autopilots.md, "Ground stations"):
//   gcs_relay FOLDER [PORT]
// Each UDP datagram that reaches the node on PORT (default 14550) goes to FOLDER/mavlink.sock,
// and its sender is remembered as a vehicle. Each datagram that reaches FOLDER/commands.sock
// (bound here) goes to every vehicle heard so far, from PORT: a vehicle's MAVLink ignores
// messages for other system ids, as a MAVLink router without a route for the target sends to
// every link. Datagrams are dropped, and counted, when the host's socket is absent or full (a
// Unix datagram queue holds about ten): telemetry is lossy, and a GCS resends its commands.
// Prints "relaying" once both sockets are bound.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

constexpr size_t kMaxVehicles = 256;  // a fleet; more senders than this are not answered
constexpr size_t kMaxDatagramBytes = 65536;

volatile std::sig_atomic_t g_stop = 0;
void OnSignal(int) { g_stop = 1; }

[[noreturn]] void Die(const std::string& message) {
  std::fprintf(stderr, "gcs_relay: %s: %s\n", message.c_str(), std::strerror(errno));
  std::exit(1);
}

sockaddr_un UnixAddress(const std::string& path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.size() >= sizeof address.sun_path) {
    errno = ENAMETOOLONG;
    Die(path);
  }
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  return address;
}

bool SameSender(const sockaddr_in& a, const sockaddr_in& b) {
  return a.sin_addr.s_addr == b.sin_addr.s_addr && a.sin_port == b.sin_port;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: gcs_relay FOLDER [PORT]\n");
    return 2;
  }
  const std::string folder = argv[1];
  const int port = argc == 3 ? std::atoi(argv[2]) : 14550;
  if (port <= 0 || port > 65535) {
    std::fprintf(stderr, "gcs_relay: port '%s' is not one\n", argv[2]);
    return 2;
  }
  std::signal(SIGTERM, OnSignal);
  std::signal(SIGINT, OnSignal);

  const int radio = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (radio < 0) Die("socket");
  sockaddr_in any{};
  any.sin_family = AF_INET;
  any.sin_port = htons(static_cast<uint16_t>(port));
  if (bind(radio, reinterpret_cast<const sockaddr*>(&any), sizeof any) != 0) {
    Die("bind UDP " + std::to_string(port));
  }
  const int host = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (host < 0) Die("socket");
  const sockaddr_un commands = UnixAddress(folder + "/commands.sock");
  unlink(commands.sun_path);  // a previous relay's: the folder is this relay's to use
  if (bind(host, reinterpret_cast<const sockaddr*>(&commands), sizeof commands) != 0) {
    Die(std::string("bind ") + commands.sun_path);
  }
  const sockaddr_un telemetry = UnixAddress(folder + "/mavlink.sock");
  std::printf("relaying UDP %d <-> %s, %s\n", port, telemetry.sun_path, commands.sun_path);
  std::fflush(stdout);

  std::vector<sockaddr_in> vehicles;
  long long dropped = 0;
  std::vector<char> buffer(kMaxDatagramBytes);
  while (!g_stop) {
    pollfd ready[2] = {{radio, POLLIN, 0}, {host, POLLIN, 0}};
    if (poll(ready, 2, -1) < 0) {
      if (errno == EINTR) continue;
      Die("poll");
    }
    if (ready[0].revents & POLLIN) {
      sockaddr_in from{};
      socklen_t from_size = sizeof from;
      const ssize_t n = recvfrom(radio, buffer.data(), buffer.size(), MSG_DONTWAIT,
                                 reinterpret_cast<sockaddr*>(&from), &from_size);
      if (n >= 0) {
        bool known = false;
        for (const sockaddr_in& vehicle : vehicles) known = known || SameSender(vehicle, from);
        if (!known && vehicles.size() < kMaxVehicles) {
          vehicles.push_back(from);
          std::printf("vehicle %s:%d\n", inet_ntoa(from.sin_addr), ntohs(from.sin_port));
          std::fflush(stdout);
        }
        if (sendto(host, buffer.data(), n, MSG_DONTWAIT,
                   reinterpret_cast<const sockaddr*>(&telemetry), sizeof telemetry) < 0) {
          ++dropped;
        }
      }
    }
    if (ready[1].revents & POLLIN) {
      const ssize_t n = recv(host, buffer.data(), buffer.size(), MSG_DONTWAIT);
      for (const sockaddr_in& vehicle : vehicles) {
        if (n < 0) break;
        sendto(radio, buffer.data(), n, MSG_DONTWAIT, reinterpret_cast<const sockaddr*>(&vehicle),
               sizeof vehicle);
      }
    }
  }
  std::printf("stopped; %lld datagrams to the host dropped\n", dropped);
  unlink(commands.sun_path);
  return 0;
}
