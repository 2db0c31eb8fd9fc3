// ns-3 3.37's packet error rate tables for BCC-coded OFDM (data in
// per_tables.cc; source and provenance there and in docs/references.md).
#ifndef SITLNET_MAC_PHY_SIM_PER_TABLES_H_
#define SITLNET_MAC_PHY_SIM_PER_TABLES_H_

namespace sitlnet::mac {

// PER of a reference frame size at SNRs first_snr_db, first_snr_db + 0.5,
// ...: below the first point the PER is 1, above the last (always 0) it is 0.
struct PerTable {
  double first_snr_db = 0;
  const double* per = nullptr;
  int size = 0;
};
inline constexpr double kPerTableStepDb = 0.5;
inline constexpr int kPerTableMcsCount = 10;  // MCS 0-9: BPSK 1/2 .. 256-QAM 5/6.
// Reference frame sizes of the two tables (ns-3's ERROR_TABLE_BCC_SMALL_FRAME_SIZE
// and ..._LARGE_FRAME_SIZE).
inline constexpr int kSmallTableFrameBytes = 32;
inline constexpr int kLargeTableFrameBytes = 1458;

// The table of `mcs` (0..9) for small (32-byte) or large (1458-byte) frames.
const PerTable& BccPerTable(int mcs, bool large_frame);

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_PER_TABLES_H_
