#include "runner/medium_records.h"

#include <cstdio>
#include <ctime>

#include "run_formats/run_formats.h"
#include "runner/summary.h"

namespace sitlnet::runner {

MediumRecords::MediumRecords(const std::string& run_dir, int robots, bool lockstep,
                             run_formats::LossLog* losses)
    : pcap_(run_dir + "/medium.pcap", "", 256, "pcap"),
      epoch_offset_ns_(lockstep ? 0 : static_cast<TimeNs>(std::time(nullptr)) * kNsPerS),
      deliveries_(run_dir + "/deliveries.csv", run_formats::kDeliveryHeader),
      connectivity_(robots, kConnectivityWindowNs, kConnectivitySampleNs),
      losses_(losses) {
  pcap_.AppendRecord(tapbridge::PcapFileHeader());  // Buffered: written with the first records.
}

void MediumRecords::Attach(tapbridge::BridgeCore* bridge) {
  bridge->AddAirFrameObserver([this](const tapbridge::AirFrame& frame) {
    pcap_.AppendRecord(tapbridge::EncodePcapRecord(frame, epoch_offset_ns_));
  });
  bridge->AddDeliveryObserver([this](const tapbridge::Delivery& d) {
    connectivity_.Heard(d.delivery_ns, d.source, d.station);
    char line[128];
    std::snprintf(line, sizeof line, "%lld,%d,%d,%.2f,%.2f", static_cast<long long>(d.delivery_ns),
                  d.source, d.station, d.rx_power_dbm, d.sinr_db);
    deliveries_.Append(line);
  });
}

void MediumRecords::Flush() {
  deliveries_.Flush();
  pcap_.Flush();
  if (losses_) losses_->Finish();
}

}  // namespace sitlnet::runner
