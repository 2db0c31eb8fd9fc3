// Sends every on-air frame, pcap-encoded once, to the --pcap file and to the
// live subscribers of the control socket.
#ifndef SITLNET_TAPBRIDGE_PCAP_FANOUT_H_
#define SITLNET_TAPBRIDGE_PCAP_FANOUT_H_

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {

class PcapFanout {
 public:
  // Timestamps are `epoch_offset_ns` (CLOCK_REALTIME of virtual time 0) plus
  // the virtual start of each frame.
  explicit PcapFanout(TimeNs epoch_offset_ns) : epoch_offset_ns_(epoch_offset_ns) {}
  ~PcapFanout();

  // Creates (truncates) `path` and writes the pcap file header. Throws Error.
  void OpenFile(const std::string& path);
  // A subscriber receives the bytes of the stream through `send`, which
  // returns false if it cannot take them now (the record is then dropped
  // whole and counted, so the stream stays parseable).
  int AddSubscriber(std::function<bool(const std::string&)> send);
  void RemoveSubscriber(int id);
  bool active() const { return file_fd_.valid() || !subscribers_.empty(); }

  void OnFrame(const AirFrame& frame);

  uint64_t records() const { return records_; }
  uint64_t subscriber_drops() const { return subscriber_drops_; }

 private:
  struct Subscriber {
    int id;
    std::function<bool(const std::string&)> send;
  };
  TimeNs epoch_offset_ns_;
  UniqueFd file_fd_;
  std::string file_path_;
  std::vector<Subscriber> subscribers_;
  int next_id_ = 1;
  uint64_t records_ = 0;
  uint64_t subscriber_drops_ = 0;
};

}  // namespace sitlnet::tapbridge

#endif  // SITLNET_TAPBRIDGE_PCAP_FANOUT_H_
