// The live view's autopilot modes: medium.pcap of the running run, read from where the last
// read ended, on the server's thread when /api/live is rebuilt (at most every 200 ms). The
// run's threads do nothing for it; the pcap reaches the file every 256 frames, so a mode shows
// that much later.
#ifndef SITLNET_VIEW_LIVE_MODES_H_
#define SITLNET_VIEW_LIVE_MODES_H_

#include <string>
#include <vector>

#include "common/common.h"
#include "view/air_modes.h"

namespace sitlnet::view {

class LiveModes {
 public:
  LiveModes(const std::string& run_dir, int robots);
  ~LiveModes();
  LiveModes(const LiveModes&) = delete;
  LiveModes& operator=(const LiveModes&) = delete;

  // Reads what was appended to medium.pcap since the last call. Call only once the run has
  // begun its loop: before, the folder may still hold an earlier run's file. A file that is not
  // sitlnet's pcap stops the reading (the modes stay as they were), said once on stderr.
  void Update();
  // Each robot's latest mode change, by robot index (robots with none left out).
  std::vector<ModeChange> Latest() const;

 private:
  std::string path_;
  int robots_;
  UniqueFd fd_;
  bool failed_ = false;
  AirModeReader reader_;
};

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_LIVE_MODES_H_
