// The relay's thread: one poll over the station's socket, every host endpoint and a stop event.
#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <mutex>
#include <thread>

#include "gcs_link/frame_stream.h"
#include "gcs_link/gcs_link.h"
#include "gcs_link/host_endpoint.h"
#include "gcs_link/station_socket.h"
#include "gcs_link/tlog_writer.h"
#include "gcs_link/vehicle_tally.h"

namespace sitlnet::gcs {
namespace {

constexpr int kMaxStationReadsPerWake = 256;  // So that the vehicles cannot starve a GCS.

std::unique_ptr<HostEndpoint> MakeHostEndpoint(const GcsEndpoint& endpoint) {
  switch (endpoint.kind) {
    case GcsEndpoint::Kind::kUdp:
      return MakeUdpEndpoint(endpoint);
    case GcsEndpoint::Kind::kTcpListen:
      return MakeTcpListenEndpoint(endpoint);
  }
  SITLNET_DEMAND(false);
}

}  // namespace

struct GcsRelay::Impl {
  explicit Impl(const GcsRelayOptions& options)
      : station(options.station_netns, options.station_port) {
    SITLNET_DEMAND(!options.endpoints.empty());
    for (const GcsEndpoint& endpoint : options.endpoints) {
      hosts.push_back(MakeHostEndpoint(endpoint));
      description += (description.empty() ? "" : ", ") + endpoint.text;
    }
    if (!options.tlog_path.empty()) tlog = std::make_unique<TlogWriter>(options.tlog_path);
    stop_event.Reset(eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC));
    if (!stop_event.valid()) throw Error(SystemErrorMessage("eventfd for the GCS relay", errno));
    thread = std::thread([this] { Loop(); });
  }

  void Loop() {
    std::vector<pollfd> fds;
    std::vector<uint8_t> datagram;
    const GcsBytesSink to_vehicles = [this](const uint8_t* data, size_t size) {
      if (tlog) tlog->AppendDatagram(VirtualNow(), data, size, &counters);
      station.SendToVehicles(data, size, &counters);
    };
    while (true) {
      fds.clear();
      fds.push_back({stop_event.get(), POLLIN, 0});
      fds.push_back({station.fd(), POLLIN, 0});
      for (const auto& host : hosts) host->AppendPollFds(&fds);
      if (poll(fds.data(), fds.size(), -1) < 0) {
        if (errno == EINTR) continue;
        std::fprintf(stderr, "sitlnet run: the GCS relay stopped: %s\n",
                     SystemErrorMessage("poll", errno).c_str());
        return;
      }
      if (fds[0].revents != 0) return;
      const std::lock_guard<std::mutex> lock(counters_mutex);
      if (fds[1].revents != 0) {
        for (int i = 0; i < kMaxStationReadsPerWake && station.Receive(&datagram, &counters); ++i) {
          if (tlog) tlog->AppendDatagram(VirtualNow(), datagram.data(), datagram.size(), &counters);
          ForEachFrame(datagram.data(), datagram.size(),
                       [this](const uint8_t* frame, size_t bytes) {
                         tally.Count(frame, bytes, station.last_sender());
                       });
          for (const auto& host : hosts)
            host->SendToGcs(datagram.data(), datagram.size(), &counters);
        }
      }
      for (size_t i = 2; i < fds.size(); ++i) {
        if (fds[i].revents == 0) continue;
        for (const auto& host : hosts) {
          if (host->HandleReady(fds[i], to_vehicles, &counters)) break;
        }
      }
    }
  }

  TimeNs VirtualNow() const {
    if (timebase_ready.load(std::memory_order_acquire)) return timebase.VirtualOf(MonotonicNowNs());
    return virtual_ns.load();
  }

  void Stop() {
    if (!thread.joinable()) return;
    const uint64_t one = 1;
    SITLNET_DEMAND(write(stop_event.get(), &one, sizeof one) == sizeof one);
    thread.join();
    if (tlog) tlog->Close();
  }

  StationSocket station;
  std::vector<std::unique_ptr<HostEndpoint>> hosts;
  std::unique_ptr<TlogWriter> tlog;
  VehicleTally tally;  // Guarded by counters_mutex while the thread runs.
  std::string description;
  UniqueFd stop_event;
  std::atomic<TimeNs> virtual_ns{0};
  clock::Timebase timebase;  // Written once, before timebase_ready is set.
  std::atomic<bool> timebase_ready{false};
  mutable std::mutex counters_mutex;
  GcsRelayCounters counters;  // Guarded by counters_mutex while the thread runs.
  std::thread thread;
};

GcsRelay::GcsRelay(const GcsRelayOptions& options) : impl_(std::make_unique<Impl>(options)) {}

GcsRelay::~GcsRelay() {
  if (impl_ == nullptr) return;
  try {
    impl_->Stop();
  } catch (const Error& error) {
    std::fprintf(stderr, "sitlnet run: %s\n", error.what());
  }
}

void GcsRelay::SetVirtualNow(TimeNs virtual_ns) { impl_->virtual_ns.store(virtual_ns); }

void GcsRelay::UseTimebase(const clock::Timebase& timebase) {
  SITLNET_DEMAND(!impl_->timebase_ready.load());
  impl_->timebase = timebase;
  impl_->timebase_ready.store(true, std::memory_order_release);
}

void GcsRelay::Stop() { impl_->Stop(); }

GcsRelayCounters GcsRelay::counters() const {
  const std::lock_guard<std::mutex> lock(impl_->counters_mutex);
  GcsRelayCounters counters = impl_->counters;
  counters.vehicles = impl_->tally.vehicles();
  return counters;
}

std::string GcsRelay::Describe() const { return impl_->description; }

}  // namespace sitlnet::gcs
