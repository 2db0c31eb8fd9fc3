// EDCA's classification and parameters: a frame's user priority from its IP header, the
// user priority's access category, and each category's default contention parameters.
#include "mac_phy_sim/phy_mode.h"

namespace sitlnet::mac {

int UserPriorityOf(std::span<const uint8_t> ethernet_frame) {
  // Linux's cfg80211_classify8021d before 6.8 (and ns-3 3.37's socket priority of a packet
  // whose IP_TOS is set): the DS field's top three bits, the old IP precedence.
  if (ethernet_frame.size() < 16) return 0;
  const int ethertype = ethernet_frame[12] << 8 | ethernet_frame[13];
  if (ethertype == 0x0800) return ethernet_frame[15] >> 5;  // IPv4: TOS byte.
  if (ethertype == 0x86dd) return (ethernet_frame[14] & 0x0f) >> 1;  // IPv6: traffic class.
  return 0;  // ARP and every other non-IP frame: best effort.
}

AccessCategory AccessCategoryOf(int user_priority) {
  // IEEE 802.11-2016 Table 10-1 (ns-3 3.37's QosUtilsMapTidToAc).
  switch (user_priority) {
    case 1:
    case 2:
      return AccessCategory::kBackground;
    case 4:
    case 5:
      return AccessCategory::kVideo;
    case 6:
    case 7:
      return AccessCategory::kVoice;
    default:
      return AccessCategory::kBestEffort;
  }
}

EdcaParameters DefaultEdcaParameters(AccessCategory ac, int cw_min, int cw_max, bool dsss) {
  // ns-3 3.37 WifiMac::ConfigureDcf, after IEEE 802.11-2016 Table 9-137 (default EDCA
  // Parameter Set), with aCWmin/aCWmax of the PHY. The standard gives AC_BE and AC_BK a
  // TXOP limit of 2.528 ms (OFDM) or 3.264 ms (DSSS); ns-3 sets 0 there ("TODO should
  // be"), and so does this model.
  switch (ac) {
    case AccessCategory::kVoice:
      return {2, (cw_min + 1) / 4 - 1, (cw_min + 1) / 2 - 1, (dsss ? 3264 : 2080) * kNsPerUs};
    case AccessCategory::kVideo:
      return {2, (cw_min + 1) / 2 - 1, cw_min, (dsss ? 6016 : 4096) * kNsPerUs};
    case AccessCategory::kBestEffort:
      return {3, cw_min, cw_max, 0};
    case AccessCategory::kBackground:
      return {7, cw_min, cw_max, 0};
  }
  return {};
}

}  // namespace sitlnet::mac
