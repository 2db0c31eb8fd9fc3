// The medium daemon's control socket: length-prefixed protobuf requests
// (proto/sitlnet/medium.proto) over a Unix stream socket, served on the
// daemon's event loop. Non-blocking throughout: a slow client never stalls
// the medium; a slow pcap subscriber loses whole records (counted).
#ifndef SITLNET_TAPBRIDGE_CONTROL_SERVER_H_
#define SITLNET_TAPBRIDGE_CONTROL_SERVER_H_

#include <map>
#include <memory>
#include <string>

#include "sitlnet/medium.pb.h"
#include "tapbridge/pcap_fanout.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {

// True if something accepts connections on `path` (a live daemon).
bool ControlSocketAnswers(const std::string& path);

class ControlServer {
 public:
  // Binds `path` (removing a stale socket; refusing if a daemon answers on it).
  // Throws Error.
  ControlServer(const std::string& path, EventLoop* loop, BridgeCore* core, PcapFanout* fanout);
  ~ControlServer();

  proto::MediumStatus Status() const;

 private:
  struct Connection {
    UniqueFd fd;
    std::string in;
    std::string out;
    int subscriber_id = 0;  // Nonzero once subscribed to the pcap stream.
    bool want_out = false;  // EPOLLOUT registered.
  };
  void Accept();
  void OnEvent(int fd, uint32_t events);
  void HandleRequest(Connection* c, const std::string& bytes);
  void Flush(Connection* c);
  void Close(int fd);

  std::string path_;
  EventLoop* loop_;
  BridgeCore* core_;
  PcapFanout* fanout_;
  UniqueFd listen_fd_;
  std::map<int, std::unique_ptr<Connection>> connections_;
};

}  // namespace sitlnet::tapbridge

#endif  // SITLNET_TAPBRIDGE_CONTROL_SERVER_H_
