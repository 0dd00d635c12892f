#include "runtime/room.h"

#include <algorithm>

namespace rcx {
namespace {

bool running(const Machine& m) { return m.stop().kind == StopKind::Running; }

// The packets of one brick, in the order they go on the air. It has one
// transmitter, so they never overlap: their starts and their ends rise
// together, which lets the room find the next packet to end, and a packet's
// overlaps, without going through every packet ever sent (a program that
// sends in a loop for minutes queues tens of thousands).
struct Queue {
  std::vector<std::size_t> packets;  // indices into the room's list
  std::size_t decided = 0;           // how many of them (the first) are delivered or lost
  Micros transmitter_free = 0;
  bool switched_off = false;         // its power-off has cut its queue short
};

// Another brick's packet on the air at the same time as `t`: a receiver
// hears the two sets of pulses at once, which no longer check (complements,
// checksum).
bool overlapped(const Transmission& t, const Queue& other, const std::vector<Transmission>& sent) {
  auto first_ending_after_start = std::ranges::partition_point(
      other.packets, [&](std::size_t k) { return sent[k].end_us <= t.start_us; });
  if (first_ending_after_start == other.packets.end()) return false;
  // A packet that never went out (its brick switched off) is [off, off): no time on the air.
  const Transmission& p = sent[*first_ending_after_start];
  return p.start_us < p.end_us && p.start_us < t.end_us;
}

}  // namespace

std::vector<Transmission> run_room(std::span<Machine* const> machines, Micros limit_us) {
  const std::size_t n = machines.size();
  std::vector<Transmission> sent;
  std::vector<Queue> queues(n);
  std::vector<std::size_t> seen(n, 0);  // each machine's events already looked at
  auto first_undecided = [&](const Queue& q) -> const Transmission* {
    return q.decided < q.packets.size() ? &sent[q.packets[q.decided]] : nullptr;
  };
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
    bool undecided = std::ranges::any_of(queues, [&](const Queue& q) { return first_undecided(q) != nullptr; });
    bool any_running = std::ranges::any_of(machines, [](const Machine* m) { return running(*m); });
    if ((!any_running && !undecided) || now >= limit_us) break;
    Micros earliest = limit_us;
    for (const Machine* m : machines)
      if (running(*m)) earliest = std::min(earliest, m->next_activity_us());
    Micros next = std::min(std::max(now, earliest) + kMessageAirUs, limit_us);
    for (const Queue& q : queues)
      if (const Transmission* t = first_undecided(q)) next = std::min(next, t->end_us);
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
        Queue& q = queues[i];
        Transmission t;
        t.from = static_cast<int>(i);
        t.value = e.value;
        t.sent_us = e.t_us;
        t.start_us = std::max(e.t_us, q.transmitter_free);
        t.end_us = t.start_us + kMessageAirUs;
        q.transmitter_free = t.end_us;
        q.packets.push_back(sent.size());
        sent.push_back(t);
      }
    }
    // A brick that switched itself off (SleepNow; the idle timer never
    // runs out while a program runs) stops transmitting: what it had queued
    // never goes out, and a packet it was sending stops where it was (still
    // garbling what it overlapped), which no receiver takes. Its power-off is
    // found in the round it happened, before any packet that ends after it
    // is decided.
    for (std::size_t i = 0; i < n; ++i) {
      Queue& q = queues[i];
      if (machines[i]->stop().kind != StopKind::PowerOff || q.switched_off) continue;
      q.switched_off = true;
      const Micros off_us = machines[i]->now_us();
      for (std::size_t k = q.decided; k < q.packets.size(); ++k) {
        Transmission& t = sent[q.packets[k]];
        if (t.end_us <= off_us) continue;
        t.switched_off = true;
        t.start_us = std::min(t.start_us, off_us);
        t.end_us = off_us;
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      Queue& q = queues[i];
      for (; q.decided < q.packets.size() && sent[q.packets[q.decided]].end_us <= now; ++q.decided) {
        Transmission& t = sent[q.packets[q.decided]];
        if (t.switched_off) continue;
        for (std::size_t j = 0; j < n; ++j)
          if (j != i && overlapped(t, queues[j], sent)) t.collided = true;
        if (t.collided) continue;
        for (std::size_t j = 0; j < n; ++j)
          if (j != i && running(*machines[j])) {
            machines[j]->schedule(TimedInput{t.end_us, MessageInput{t.value}});
            t.received_by.push_back(static_cast<int>(j));
          }
      }
    }
  }
  // What had not ended by the limit reached nobody, and is not a collision
  // or a message to an empty room either.
  for (const Queue& q : queues)
    for (std::size_t k = q.decided; k < q.packets.size(); ++k) sent[q.packets[k]].unfinished = true;
  for (Machine* m : machines) m->run(limit_us);
  std::ranges::stable_sort(sent, {}, &Transmission::start_us);
  return sent;
}

}  // namespace rcx
