// Event scheduler: one queue of (time_ns, sequence) ordered events, injected
// into the medium (no global clock). Equal times run in insertion order,
// which makes every run with the same inputs identical. Cancellation is lazy:
// events carry a generation number the handler compares with the owner's.
// Backoff expiries are not in this queue: they change on every busy/idle
// edge of every station, so the medium keeps them per station and takes the
// earliest by a scan (see Medium::State::EarliestAccess).
#ifndef SITLNET_MAC_PHY_SIM_SCHEDULER_H_
#define SITLNET_MAC_PHY_SIM_SCHEDULER_H_

#include <cstdint>
#include <queue>
#include <vector>

#include "common/common.h"

namespace sitlnet::mac {

enum class EventType : uint8_t {
  kEnqueue,      // A submitted frame reaches its station's queue (aux: pending frame slot).
  kMove,         // A position update takes effect (aux: pending move slot).
  kTxEnd,        // A transmission leaves the air (aux: transmission id).
  kTimeout,      // ACK/CTS timeout of `station` (aux: timeout generation).
  kRespond,      // `station` sends its pending SIFS response (ACK, CTS, DATA after CTS).
  kNavEnd,       // The NAV of `station` may have expired.
  kSignalStart,  // A delayed signal reaches its receiver (aux: tx id << 32 | entry index).
  kSignalEnd,    // A delayed signal leaves its receiver (aux: as kSignalStart).
  kContinueTxop,  // `station` goes on with its TXOP (aux: the access category).
  kBlockAckReqDue,  // `station` sends a BlockAckReq a SIFS after a BlockAck (aux: the category).
};

struct Event {
  TimeNs time_ns = 0;
  uint64_t sequence = 0;
  uint64_t aux = 0;
  int32_t station = 0;
  EventType type = EventType::kEnqueue;
};

class Scheduler {
 public:
  void Push(TimeNs time_ns, EventType type, int station, uint64_t aux) {
    heap_.push(Event{time_ns, next_sequence_++, aux, station, type});
  }
  bool empty() const { return heap_.empty(); }
  const Event& top() const { return heap_.top(); }
  Event Pop() {
    Event event = heap_.top();
    heap_.pop();
    return event;
  }
  size_t size() const { return heap_.size(); }

 private:
  struct Later {
    bool operator()(const Event& a, const Event& b) const {
      return a.time_ns != b.time_ns ? a.time_ns > b.time_ns : a.sequence > b.sequence;
    }
  };
  std::priority_queue<Event, std::vector<Event>, Later> heap_;
  uint64_t next_sequence_ = 0;
};

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_SCHEDULER_H_
