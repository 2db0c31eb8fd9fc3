// One epoll loop with per-fd callbacks and an after-batch hook.
#include <sys/epoll.h>
#include <unistd.h>

#include <cerrno>
#include <unordered_map>

#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {

struct EventLoop::Impl {
  UniqueFd epoll_fd;
  bool stopped = false;
  // Callbacks by fd; a callback may Remove its own or other fds, so dispatch
  // looks each fd up again rather than holding iterators.
  std::unordered_map<int, std::shared_ptr<std::function<void(uint32_t)>>> callbacks;
  std::function<void()> after_batch;
  std::shared_ptr<const int> lifetime = std::make_shared<const int>(0);
};

EventLoop::EventLoop() : impl_(std::make_unique<Impl>()) {
  impl_->epoll_fd.Reset(epoll_create1(EPOLL_CLOEXEC));
  if (!impl_->epoll_fd.valid()) throw Error(SystemErrorMessage("epoll_create1", errno));
}

EventLoop::~EventLoop() = default;

void EventLoop::Add(int fd, uint32_t events, std::function<void(uint32_t)> callback) {
  epoll_event event{};
  event.events = events;
  event.data.fd = fd;
  if (epoll_ctl(impl_->epoll_fd.get(), EPOLL_CTL_ADD, fd, &event) != 0) {
    throw Error(SystemErrorMessage("epoll_ctl add fd " + std::to_string(fd), errno));
  }
  impl_->callbacks[fd] = std::make_shared<std::function<void(uint32_t)>>(std::move(callback));
}

void EventLoop::Modify(int fd, uint32_t events) {
  epoll_event event{};
  event.events = events;
  event.data.fd = fd;
  if (epoll_ctl(impl_->epoll_fd.get(), EPOLL_CTL_MOD, fd, &event) != 0) {
    throw Error(SystemErrorMessage("epoll_ctl mod fd " + std::to_string(fd), errno));
  }
}

void EventLoop::Remove(int fd) {
  epoll_ctl(impl_->epoll_fd.get(), EPOLL_CTL_DEL, fd, nullptr);
  impl_->callbacks.erase(fd);
}

void EventLoop::SetAfterBatch(std::function<void()> callback) {
  impl_->after_batch = std::move(callback);
}

void EventLoop::RunOnce(int timeout_ms) {
  epoll_event events[64];
  const int n = epoll_wait(impl_->epoll_fd.get(), events, 64, timeout_ms);
  if (n < 0 && errno != EINTR) throw Error(SystemErrorMessage("epoll_wait", errno));
  for (int i = 0; i < n; ++i) {
    const auto it = impl_->callbacks.find(events[i].data.fd);
    if (it == impl_->callbacks.end()) continue;
    const auto callback = it->second;  // Keeps it alive if it removes itself.
    (*callback)(events[i].events);
  }
  if (impl_->after_batch) impl_->after_batch();
}

void EventLoop::Run() {
  while (!impl_->stopped) RunOnce(-1);
}

void EventLoop::Stop() { impl_->stopped = true; }
bool EventLoop::stopped() const { return impl_->stopped; }
std::weak_ptr<const void> EventLoop::lifetime() const { return impl_->lifetime; }

}  // namespace sitlnet::tapbridge
