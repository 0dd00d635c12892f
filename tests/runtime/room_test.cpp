// Several bricks in one room (runtime/room.h): a Send message reaches the
// other bricks when its packet has been on the air 41.25 ms; packets of two
// bricks on the air together are both lost; a room of one is a plain run.
#include <gtest/gtest.h>

#include <chrono>
#include <vector>

#include "runtime/room.h"
#include "runtime/vm.h"
#include "tests/runtime/vm_support.h"

using namespace vmtest;
using rcx::kMicrosPerMs;

namespace {

// Waits while the message buffer holds 0, then copies it into var 0.
Bytes wait_for_message() { return code({chk(3, IMM, 0, MESSAGE, 0, -6), setv(0, MESSAGE, 0)}); }

struct Room {
  std::vector<rcx::Machine> machines;
  std::vector<rcx::Transmission> sent;

  explicit Room(std::initializer_list<Bytes> programs, long limit_ms = 2000) {
    machines.reserve(programs.size());
    for (const Bytes& program : programs) {
      machines.emplace_back();
      machines.back().load(0, image({{0, program}}));
      machines.back().start_program();
    }
    std::vector<rcx::Machine*> room;
    for (auto& m : machines) room.push_back(&m);
    sent = rcx::run_room(room, limit_ms * kMicrosPerMs);
  }
};

}  // namespace

TEST(Room, APacketBuiltFromTheSeedsFramingTakes41MsAt2400Baud) {
  // 9 bytes of 11 bits at 2400 baud.
  EXPECT_EQ(rcx::kMessageAirUs, 41'250);
}

TEST(Room, AMessageArrivesWhenItsPacketEnds) {
  Room room({msgsend(IMM, 42), wait_for_message()});
  ASSERT_EQ(room.sent.size(), 1u);
  const rcx::Transmission& t = room.sent[0];
  EXPECT_EQ(t.from, 0);
  EXPECT_EQ(t.value, 42);
  EXPECT_EQ(t.start_us, 0);
  EXPECT_EQ(t.end_us, 41'250);
  EXPECT_FALSE(t.collided);
  EXPECT_EQ(t.received_by, std::vector<int>{1});
  auto received = events_of(room.machines[1], rcx::EventKind::MessageReceived);
  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].value, 42);
  // At the first instruction boundary at or after the packet's end (2 ms each).
  EXPECT_EQ(received[0].t_us, 42 * kMicrosPerMs);
  EXPECT_EQ(var(room.machines[1], 0), 42);
  EXPECT_EQ(room.machines[1].stop().kind, rcx::StopKind::Ended);
  // The sender does not hear itself.
  EXPECT_TRUE(events_of(room.machines[0], rcx::EventKind::MessageReceived).empty());
  EXPECT_EQ(room.machines[0].state().message, 0);
}

TEST(Room, TwoBricksPacketsOnTheAirTogetherAreBothLost) {
  // Bricks 0 and 1 send 1 ms apart; brick 2 listens and hears nothing.
  Room room({msgsend(IMM, 7), code({set(1, 0), msgsend(IMM, 8)}), wait_for_message()});
  ASSERT_EQ(room.sent.size(), 2u);
  EXPECT_TRUE(room.sent[0].collided);
  EXPECT_TRUE(room.sent[1].collided);
  EXPECT_TRUE(room.sent[0].received_by.empty());
  EXPECT_TRUE(events_of(room.machines[2], rcx::EventKind::MessageReceived).empty());
  EXPECT_EQ(room.machines[2].stop().kind, rcx::StopKind::TimeLimit);
}

TEST(Room, PacketsOneAfterTheOtherBothArrive) {
  // Brick 1 sends at 44 ms, after brick 0's packet (0 to 41.25 ms) ended.
  Room room({msgsend(IMM, 7), code({wait(4), set(1, 0), msgsend(IMM, 8)}),
             code({wait_for_message(), msgclr(), setv(1, VAR, 0), wait_for_message()})});
  ASSERT_EQ(room.sent.size(), 2u);
  EXPECT_FALSE(room.sent[0].collided);
  EXPECT_FALSE(room.sent[1].collided);
  EXPECT_EQ(room.sent[1].start_us, 42 * kMicrosPerMs);
  EXPECT_EQ(var(room.machines[2], 1), 7);
  EXPECT_EQ(var(room.machines[2], 0), 8);
  // Brick 1, waiting, hears brick 0's packet; brick 0 has ended by the time
  // brick 1's arrives.
  EXPECT_EQ(room.sent[0].received_by, (std::vector<int>{1, 2}));
  EXPECT_EQ(room.sent[1].received_by, (std::vector<int>{2}));
}

TEST(Room, ABricksSecondMessageFollowsItsFirstOnTheAir) {
  // Sent 2 ms apart by one brick: one transmitter, so the second goes out
  // when the first has; neither garbles the other.
  Room room({code({msgsend(IMM, 3), msgsend(IMM, 4)}), code({wait_for_message(), msgclr(), setv(1, VAR, 0),
                                                             wait_for_message()})});
  ASSERT_EQ(room.sent.size(), 2u);
  EXPECT_EQ(room.sent[1].sent_us, 2 * kMicrosPerMs);
  EXPECT_EQ(room.sent[1].start_us, room.sent[0].end_us);
  EXPECT_FALSE(room.sent[0].collided || room.sent[1].collided);
  EXPECT_EQ(var(room.machines[1], 1), 3);
  EXPECT_EQ(var(room.machines[1], 0), 4);
}

TEST(Room, ABrickWhoseProgramEndedHearsNothing) {
  Room room({code({wait(10), msgsend(IMM, 9)}), set(0, 1)});
  ASSERT_EQ(room.sent.size(), 1u);
  EXPECT_FALSE(room.sent[0].collided);
  EXPECT_TRUE(room.sent[0].received_by.empty());
  // Its run ended when its one instruction did, not when the room's did.
  EXPECT_EQ(room.machines[1].now_us(), 2 * kMicrosPerMs);
  EXPECT_EQ(room.machines[1].stop().kind, rcx::StopKind::Ended);
}

TEST(Room, ARoomOfOneIsAPlainRun) {
  // Two tasks, waits, a send, sounds still queued at the end, a sensor input.
  auto program = image({{0, code({start(1), senstype(0, 1), sound(1), sound(2), sound(3), msgsend(IMM, 5),
                                  chk(3, IMM, 0, SENSOR, 0, -6), tone(440, 50), out(0x81)})},
                        {1, code({wait(30), setv(2, TIMER, 0), msgsend(VAR, 2), wait(20), out(0x82)})}});
  auto drive = [&](rcx::Machine& m) {
    m.load(0, program);
    m.schedule({500 * kMicrosPerMs, rcx::SensorRawInput{0, 100}});
    m.start_program();
  };
  for (long limit_ms : {300L, 2000L}) {
    rcx::Machine plain, alone;
    drive(plain);
    drive(alone);
    plain.run(limit_ms * kMicrosPerMs);
    rcx::Machine* room[] = {&alone};
    auto sent = rcx::run_room(room, limit_ms * kMicrosPerMs);
    EXPECT_EQ(sent.size(), limit_ms == 300 ? 1u : 2u);  // task 1 sends at 302 ms
    EXPECT_EQ(alone.now_us(), plain.now_us()) << limit_ms;
    EXPECT_EQ(alone.stop().kind, plain.stop().kind) << limit_ms;
    ASSERT_EQ(alone.state().events.size(), plain.state().events.size()) << limit_ms;
    for (std::size_t i = 0; i < plain.state().events.size(); ++i) {
      const rcx::Event& a = alone.state().events[i];
      const rcx::Event& b = plain.state().events[i];
      EXPECT_EQ(a.t_us, b.t_us) << i;
      EXPECT_EQ(a.kind, b.kind) << i;
      EXPECT_EQ(a.index, b.index) << i;
      EXPECT_EQ(a.value, b.value) << i;
    }
    EXPECT_EQ(alone.state().vars, plain.state().vars);
  }
}

TEST(Room, APacketStillGoingOutAtTheLimitIsUnfinishedNotLost) {
  // Sent at 0 ms into a room that stops at 10 ms: it neither collided nor
  // found the other brick gone; the run ended first.
  Room room({msgsend(IMM, 5), wait_for_message()}, 10);
  ASSERT_EQ(room.sent.size(), 1u);
  EXPECT_TRUE(room.sent[0].unfinished);
  EXPECT_FALSE(room.sent[0].collided);
  EXPECT_TRUE(room.sent[0].received_by.empty());
  Room later({msgsend(IMM, 5), wait_for_message()}, 100);
  ASSERT_EQ(later.sent.size(), 1u);
  EXPECT_FALSE(later.sent[0].unfinished);
  EXPECT_EQ(later.sent[0].received_by, std::vector<int>{1});
}

TEST(Room, BricksSendingInALoopForTenMinutesKeepUpWithTheirQueues) {
  // Each sends every 4 ms (two instructions) and its packets queue behind
  // one another 41.25 ms each: after ten minutes of virtual time each brick
  // has about 150,000 packets sent, of which some 14,500 went out. Deciding
  // each packet's fate must not look at every packet ever sent (it did, and
  // eight such bricks took a minute; now well under a second each).
  const Bytes send_forever = code({msgsend(IMM, 7), jmp(0x80 | 4)});
  auto start = std::chrono::steady_clock::now();
  Room room({send_forever, send_forever, send_forever, send_forever, send_forever, send_forever, send_forever,
             send_forever},
            600'000);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 20.0);
  ASSERT_EQ(room.sent.size(), 8u * 150'000u);
  // The eight sent in step: every packet that went out collided.
  std::size_t went_out = 0;
  for (const rcx::Transmission& t : room.sent)
    if (!t.unfinished) {
      ++went_out;
      EXPECT_TRUE(t.collided);
    }
  EXPECT_EQ(went_out, 8u * (600'000'000 / rcx::kMessageAirUs));
}

TEST(Room, ABrickThatSwitchesOffStopsTransmitting) {
  // Brick 0 sends twice and switches off at 6 ms: its first packet is cut
  // short, its second never goes out, and neither arrives (they did, from a
  // brick that was off). Brick 1's packet from 20 ms no longer meets brick
  // 0's first, which would have been on the air until 41.25 ms: it arrives.
  Room room({code({msgsend(IMM, 1), msgsend(IMM, 2), poweroff()}), code({wait(2), msgsend(IMM, 8)}),
             wait_for_message()});
  EXPECT_EQ(room.machines[0].stop().kind, rcx::StopKind::PowerOff);
  const rcx::Micros off_us = room.machines[0].now_us();
  ASSERT_EQ(room.sent.size(), 3u);
  for (const rcx::Transmission& t : room.sent) {
    if (t.from != 0) continue;
    EXPECT_TRUE(t.switched_off) << t.value;
    EXPECT_TRUE(t.received_by.empty()) << t.value;
    EXPECT_EQ(t.end_us, off_us) << t.value;
  }
  const rcx::Transmission& eight = room.sent.back();
  EXPECT_EQ(eight.value, 8);
  EXPECT_EQ(eight.start_us, 20 * kMicrosPerMs);
  EXPECT_FALSE(eight.collided);
  EXPECT_FALSE(eight.switched_off);
  EXPECT_EQ(eight.received_by, std::vector<int>{2});
  EXPECT_EQ(var(room.machines[2], 0), 8);
}
