#include "runtime/room.h"

#include <algorithm>

namespace rcx {
namespace {

bool running(const Machine& m) { return m.stop().kind == StopKind::Running; }

// Two bricks' packets on the air at the same time: a receiver hears the two
// sets of pulses at once, which no longer check (complements, checksum).
bool garble(const Transmission& a, const Transmission& b) {
  return a.from != b.from && a.start_us < b.end_us && b.start_us < a.end_us;
}

}  // namespace

std::vector<Transmission> run_room(std::span<Machine* const> machines, Micros limit_us) {
  const std::size_t n = machines.size();
  std::vector<Transmission> sent;
  std::vector<bool> arrived;                 // per packet: decided (delivered or lost)
  std::vector<std::size_t> seen(n, 0);       // each machine's events already looked at
  std::vector<Micros> transmitter_free(n, 0);
  // Every instruction that began before `now` has run on every machine, so
  // every packet that goes on the air before `now` is known. A packet's fate
  // is decided when it ends, and the machines are stopped there: by then
  // every packet that could overlap it is known, and the others have not
  // yet run past its arrival. A packet found in a round starts after the
  // round began; rounds last at most one packet's time, so it never ends
  // before the round does. Nor can one start before the earliest time a
  // machine has an instruction to run, so while every task waits the round
  // reaches one packet's time past the first wake-up (a room of waiting
  // programs asked for years goes from wake-up to wake-up, as one machine does).
  Micros now = 0;
  for (;;) {
    bool undecided = std::ranges::find(arrived, false) != arrived.end();
    bool any_running = std::ranges::any_of(machines, [](const Machine* m) { return running(*m); });
    if ((!any_running && !undecided) || now >= limit_us) break;
    Micros earliest = limit_us;
    for (const Machine* m : machines)
      if (running(*m)) earliest = std::min(earliest, m->next_activity_us());
    Micros next = std::min(std::max(now, earliest) + kMessageAirUs, limit_us);
    for (std::size_t k = 0; k < sent.size(); ++k)
      if (!arrived[k]) next = std::min(next, sent[k].end_us);
    for (Machine* m : machines)
      if (running(*m)) m->run_while_active(next);
    now = next;
    for (std::size_t i = 0; i < n; ++i) {
      const std::vector<Event>& events = machines[i]->state().events;
      for (; seen[i] < events.size(); ++seen[i]) {
        const Event& e = events[seen[i]];
        if (e.kind != EventKind::MessageSent) continue;
        // One transmitter per brick: a message sent while the last one is
        // still going out follows it.
        Transmission t;
        t.from = static_cast<int>(i);
        t.value = e.value;
        t.sent_us = e.t_us;
        t.start_us = std::max(e.t_us, transmitter_free[i]);
        t.end_us = t.start_us + kMessageAirUs;
        transmitter_free[i] = t.end_us;
        sent.push_back(t);
        arrived.push_back(false);
      }
    }
    for (std::size_t k = 0; k < sent.size(); ++k) {
      if (arrived[k] || sent[k].end_us > now) continue;
      arrived[k] = true;
      Transmission& t = sent[k];
      t.collided = std::ranges::any_of(sent, [&](const Transmission& other) { return garble(t, other); });
      if (t.collided) continue;
      for (std::size_t j = 0; j < n; ++j)
        if (static_cast<int>(j) != t.from && running(*machines[j])) {
          machines[j]->schedule(TimedInput{t.end_us, MessageInput{t.value}});
          t.received_by.push_back(static_cast<int>(j));
        }
    }
  }
  for (Machine* m : machines) m->run(limit_us);
  std::ranges::stable_sort(sent, {}, &Transmission::start_us);
  return sent;
}

}  // namespace rcx
