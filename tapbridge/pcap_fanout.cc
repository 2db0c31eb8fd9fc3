#include "tapbridge/pcap_fanout.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>

namespace sitlnet::tapbridge {
namespace {

// One write per record: a reader (tshark on the growing file) never sees a
// record cut by our buffering. Short writes are retried.
bool WriteAll(int fd, const std::string& bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += n;
  }
  return true;
}

}  // namespace

PcapFanout::~PcapFanout() = default;

void PcapFanout::OpenFile(const std::string& path) {
  file_fd_.Reset(open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
  if (!file_fd_.valid()) throw Error(SystemErrorMessage("create pcap file " + path, errno));
  file_path_ = path;
  if (!WriteAll(file_fd_.get(), PcapFileHeader())) {
    throw Error(SystemErrorMessage("write pcap file " + path, errno));
  }
}

int PcapFanout::AddSubscriber(std::function<bool(const std::string&)> send) {
  const int id = next_id_++;
  subscribers_.push_back(Subscriber{id, std::move(send)});
  return id;
}

void PcapFanout::RemoveSubscriber(int id) {
  std::erase_if(subscribers_, [id](const Subscriber& s) { return s.id == id; });
}

void PcapFanout::OnFrame(const AirFrame& frame) {
  if (!active()) return;
  const std::string record = EncodePcapRecord(frame, epoch_offset_ns_);
  ++records_;
  if (file_fd_.valid() && !WriteAll(file_fd_.get(), record)) {
    // A full disk must not stop the medium: stop writing the file, say so once.
    std::fprintf(stderr, "sitlnet medium: %s; pcap file closed\n",
                 SystemErrorMessage("write pcap file " + file_path_, errno).c_str());
    file_fd_.Reset();
  }
  for (const Subscriber& s : subscribers_) {
    if (!s.send(record)) ++subscriber_drops_;
  }
}

}  // namespace sitlnet::tapbridge
