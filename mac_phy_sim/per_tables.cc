// Data: the AWGN packet error rate tables of ns-3 3.37's
// TableBasedErrorRateModel for BCC-coded OFDM (src/wifi/model/reference/
// error-rate-tables.h; link-level simulations of the 802.11 PHY by the
// University of Washington, docs/references.md#ns3-table-error-model),
// carried over as data: for each MCS 0-9 (0-6 are the 802.11a/g rates other
// than 9 Mb/s, which has no MCS; 7 is 64-QAM 5/6, 8 and 9 256-QAM 3/4 and 5/6), the PER of a 32-byte and of a 1458-byte frame at
// SNRs from the first point up in 0.5 dB steps. Every table is non-increasing
// and ends at PER 0.
#include "mac_phy_sim/per_tables.h"

#include <cstddef>

namespace sitlnet::mac {
namespace {

// MCS 0, BPSK 1/2 (6 Mb/s), 32-byte frames, from -3.5 dB.
constexpr double kBcc32Mcs0[] = {1.0,    0.995,  0.9408, 0.8259,  0.5895,  0.3083, 0.1254,
                                 0.0344, 0.0085, 0.0015, 0.00024, 0.00009, 0.0};
// MCS 1, QPSK 1/2 (12 Mb/s), 32-byte frames, from -0.5 dB.
constexpr double kBcc32Mcs1[] = {1.0,    0.9921, 0.9671, 0.8349,  0.5874,  0.3169, 0.1182,
                                 0.0364, 0.0085, 0.0016, 0.00026, 0.00003, 0.0};
// MCS 2, QPSK 3/4 (18 Mb/s), 32-byte frames, from 2.0 dB.
constexpr double kBcc32Mcs2[] = {1.0,    0.994,  0.9588, 0.8512,  0.599,   0.3125, 0.1171,
                                 0.0339, 0.0078, 0.0016, 0.00028, 0.00008, 0.0};
// MCS 3, 16-QAM 1/2 (24 Mb/s), 32-byte frames, from 4.0 dB.
constexpr double kBcc32Mcs3[] = {1.0,   0.999,  0.998,  0.969,  0.8843,  0.7409,  0.4651,  0.2571,
                                 0.108, 0.0381, 0.0119, 0.0032, 0.00076, 0.00017, 0.00003, 0.0};
// MCS 4, 16-QAM 3/4 (36 Mb/s), 32-byte frames, from 8.0 dB.
constexpr double kBcc32Mcs4[] = {1.0,    0.999,  0.9479, 0.7989, 0.5923,  0.337,   0.1572,
                                 0.0542, 0.0158, 0.004,  0.0011, 0.00027, 0.00009, 0.0};
// MCS 5, 64-QAM 2/3 (48 Mb/s), 32-byte frames, from 11.5 dB.
constexpr double kBcc32Mcs5[] = {1.0,     0.998,   0.9653,  0.897,   0.7301, 0.5257,
                                 0.3058,  0.1575,  0.0646,  0.0241,  0.0079, 0.0023,
                                 0.00069, 0.00018, 0.00004, 0.00002, 0.0};
// MCS 6, 64-QAM 3/4 (54 Mb/s), 32-byte frames, from 13.0 dB.
constexpr double kBcc32Mcs6[] = {1.0,    0.9901, 0.9625, 0.8398, 0.6866,  0.4634,  0.252,   0.1145,
                                 0.0461, 0.0158, 0.0049, 0.0016, 0.00039, 0.00011, 0.00002, 0.0};
// MCS 7, 64-QAM 5/6, 32-byte frames, from 14.0 dB.
constexpr double kBcc32Mcs7[] = {1.0,    0.997,  0.9833, 0.9426, 0.8483,  0.6347,
                                 0.4377, 0.2226, 0.1111, 0.044,  0.0173,  0.0053,
                                 0.0019, 0.00052, 0.00016, 0.00004, 0.0};
// MCS 8, 256-QAM 3/4, 32-byte frames, from 17.5 dB.
constexpr double kBcc32Mcs8[] = {1.0,    0.996,  0.9804, 0.9286,  0.8225,  0.675,
                                 0.4414, 0.2666, 0.1338, 0.0595,  0.0245,  0.0091,
                                 0.0032, 0.00098, 0.00033, 0.00014, 0.00004, 0.0};
// MCS 9, 256-QAM 5/6, 32-byte frames, from 19.0 dB.
constexpr double kBcc32Mcs9[] = {1.0,    0.998,  0.9891, 0.9597, 0.875,   0.7317,
                                 0.5154, 0.3038, 0.1524, 0.0634, 0.0247,  0.0085,
                                 0.0029, 0.001,  0.00017, 0.00014, 0.00002, 0.0};
// MCS 0, BPSK 1/2 (6 Mb/s), 1458-byte frames, from -1.0 dB.
constexpr double kBcc1458Mcs0[] = {1.0,    0.994,  0.8185,  0.2908,  0.0663,
                                   0.0112, 0.0015, 0.00015, 0.00001, 0.0};
// MCS 1, QPSK 1/2 (12 Mb/s), 1458-byte frames, from 2.0 dB.
constexpr double kBcc1458Mcs1[] = {1.0, 0.997, 0.7944, 0.3008, 0.0728, 0.012, 0.0015, 0.00023, 0.0};
// MCS 2, QPSK 3/4 (18 Mb/s), 1458-byte frames, from 4.5 dB.
constexpr double kBcc1458Mcs2[] = {1.0,    0.998,  0.7578,  0.301,   0.0676,
                                   0.0122, 0.0023, 0.00035, 0.00004, 0.0};
// MCS 3, 16-QAM 1/2 (24 Mb/s), 1458-byte frames, from 7.5 dB.
constexpr double kBcc1458Mcs3[] = {1.0,    0.994,  0.8405,  0.4341,  0.1419, 0.0374,
                                   0.0086, 0.0019, 0.00036, 0.00005, 0.0};
// MCS 4, 16-QAM 3/4 (36 Mb/s), 1458-byte frames, from 11.0 dB.
constexpr double kBcc1458Mcs4[] = {1.0,   0.9269, 0.5139,  0.1826, 0.0465,
                                   0.011, 0.0026, 0.00041, 0.0001, 0.0};
// MCS 5, 64-QAM 2/3 (48 Mb/s), 1458-byte frames, from 14.5 dB.
constexpr double kBcc1458Mcs5[] = {1.0,    0.999,  0.9479,  0.6625,  0.2978,  0.1058, 0.0334,
                                   0.0091, 0.0023, 0.00064, 0.00017, 0.00002, 0.0};
// MCS 6, 64-QAM 3/4 (54 Mb/s), 1458-byte frames, from 16.0 dB.
constexpr double kBcc1458Mcs6[] = {1.0,    0.995,  0.8796, 0.5139,  0.2091,  0.0639,
                                   0.0186, 0.0046, 0.0013, 0.00023, 0.00002, 0.0};
// MCS 7, 64-QAM 5/6, 1458-byte frames, from 17.5 dB.
constexpr double kBcc1458Mcs7[] = {1.0,   0.9785, 0.7393, 0.3375,  0.1234,  0.0355,
                                   0.01,  0.0027, 0.0005, 0.00009, 0.00001, 0.0};
// MCS 8, 256-QAM 3/4, 1458-byte frames, from 21.0 dB.
constexpr double kBcc1458Mcs8[] = {1.0,    0.998,  0.9399, 0.6709,  0.3525,  0.1376, 0.0475,
                                   0.0154, 0.0052, 0.0015, 0.00036, 0.00007, 0.0};
// MCS 9, 256-QAM 5/6, 1458-byte frames, from 22.5 dB.
constexpr double kBcc1458Mcs9[] = {1.0,    0.999,  0.9506, 0.6847,  0.3261, 0.1248,  0.0409,
                                   0.013,  0.0036, 0.00082, 0.0001, 0.00002, 0.00001, 0.0};

template <std::size_t N>
constexpr PerTable Table(double first_snr_db, const double (&per)[N]) {
  return PerTable{first_snr_db, per, static_cast<int>(N)};
}

constexpr PerTable kBcc32[kPerTableMcsCount] = {Table(-3.5, kBcc32Mcs0), Table(-0.5, kBcc32Mcs1),
                                                Table(2.0, kBcc32Mcs2),  Table(4.0, kBcc32Mcs3),
                                                Table(8.0, kBcc32Mcs4),  Table(11.5, kBcc32Mcs5),
                                                Table(13.0, kBcc32Mcs6), Table(14.0, kBcc32Mcs7),
                                                Table(17.5, kBcc32Mcs8), Table(19.0, kBcc32Mcs9)};
constexpr PerTable kBcc1458[kPerTableMcsCount] = {
    Table(-1.0, kBcc1458Mcs0), Table(2.0, kBcc1458Mcs1),  Table(4.5, kBcc1458Mcs2),
    Table(7.5, kBcc1458Mcs3),  Table(11.0, kBcc1458Mcs4), Table(14.5, kBcc1458Mcs5),
    Table(16.0, kBcc1458Mcs6), Table(17.5, kBcc1458Mcs7), Table(21.0, kBcc1458Mcs8),
    Table(22.5, kBcc1458Mcs9)};

}  // namespace

const PerTable& BccPerTable(int mcs, bool large_frame) {
  return large_frame ? kBcc1458[mcs] : kBcc32[mcs];
}

}  // namespace sitlnet::mac
