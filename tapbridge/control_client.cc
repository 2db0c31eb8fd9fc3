#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {
namespace {

void ReadExactly(int fd, char* out, size_t n, const std::string& what) {
  size_t done = 0;
  while (done < n) {
    const ssize_t r = read(fd, out + done, n - done);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0)
      throw Error(r == 0 ? what + ": daemon closed the connection"
                         : SystemErrorMessage(what, errno));
    done += r;
  }
}

}  // namespace

std::string ControlSocketPath(const std::string& scenario_name) {
  return "/run/sitlnet/" + scenario_name + "/medium.sock";
}

ControlClient::ControlClient(const std::string& socket_path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (socket_path.size() >= sizeof address.sun_path) {
    throw Error("control socket path too long: " + socket_path);
  }
  std::memcpy(address.sun_path, socket_path.c_str(), socket_path.size() + 1);
  fd_.Reset(socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (!fd_.valid()) throw Error(SystemErrorMessage("socket", errno));
  if (connect(fd_.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    const int err = errno;
    throw Error(SystemErrorMessage(
        "connect to medium daemon at " + socket_path + " (is `sitlnet medium` running?)", err));
  }
}

std::string ControlClient::Call(const std::string& request_bytes) {
  std::string message(4, '\0');
  const uint32_t n = static_cast<uint32_t>(request_bytes.size());
  for (int i = 0; i < 4; ++i) message[i] = static_cast<char>((n >> (8 * i)) & 0xff);
  message += request_bytes;
  size_t done = 0;
  while (done < message.size()) {
    const ssize_t w = send(fd_.get(), message.data() + done, message.size() - done, MSG_NOSIGNAL);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) throw Error(SystemErrorMessage("send to medium daemon", errno));
    done += w;
  }
  char header[4];
  ReadExactly(fd_.get(), header, 4, "read from medium daemon");
  uint32_t length = 0;
  for (int i = 0; i < 4; ++i) length |= uint32_t{static_cast<uint8_t>(header[i])} << (8 * i);
  std::string response(length, '\0');
  ReadExactly(fd_.get(), response.data(), length, "read from medium daemon");
  return response;
}

}  // namespace sitlnet::tapbridge
