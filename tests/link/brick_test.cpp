// The virtual brick answers requests as the seed describes: replies,
// silences, download sequence rules, firmware, retransmissions.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "link/brick.h"
#include "link/session.h"
#include "rcx/opcodes.h"

namespace rcx {
namespace {

Bytes req(Op op, std::vector<int> values = {}) { return request_payload(info(op), values); }

// Sends `request` and returns the reply (nullopt = silence).
std::optional<Bytes> ask(Brick& b, const Bytes& request) { return answer(b, request); }

// Requests that differ from the previous one by the toggle, as a host sends
// them. Returns the reply's fields after checking its opcode answers the form sent.
struct Host {
  Brick& brick;
  bool toggle = false;
  std::optional<Bytes> operator()(Bytes request) {
    request = with_toggle(std::move(request), toggle);
    toggle = !toggle;
    auto reply = answer(brick, request);
    if (!reply) return std::nullopt;
    EXPECT_TRUE(answers(*reply, request)) << hex(*reply) << " for " << hex(request);
    return Bytes(reply->begin() + 1, reply->end());
  }
};

TEST(LinkBrick, AliveAnswersWithTheComplement) {
  Brick b = make_brick();
  EXPECT_EQ(ask(b, Bytes{0x10}), Bytes{0xEF});
  EXPECT_EQ(ask(b, Bytes{0x18}), Bytes{0xE7});
}

TEST(LinkBrick, VersionsNeedTheKeyAndReportRom31Firmware39) {
  Brick b = make_brick();
  EXPECT_EQ(ask(b, req(Op::GetVersions, {1, 3, 5, 7, 11})), (Bytes{0xEA, 0, 3, 0, 1, 0, 3, 0, 9}));
  EXPECT_EQ(ask(b, req(Op::GetVersions, {1, 3, 5, 7, 12})), std::nullopt);
}

TEST(LinkBrick, BatteryAndMemoryMap) {
  Brick b = make_brick();
  auto battery = ask(b, req(Op::GetBatteryPower));
  ASSERT_TRUE(battery);
  EXPECT_EQ(reply_field(info(Op::GetBatteryPower), *battery, "millivolts"), 9300);
  auto map = ask(b, req(Op::GetMemoryMap));
  ASSERT_TRUE(map);
  EXPECT_EQ(map->size(), 1u + 94 * 2);
  EXPECT_EQ((*map)[0], 0xDF);
}

TEST(LinkBrick, SetMessageHasNoReplyButSetsTheMessage) {
  Brick b = make_brick();
  EXPECT_EQ(ask(b, req(Op::SetMessage, {77})), std::nullopt);
  EXPECT_EQ(b.vm.state().message, 77);
}

TEST(LinkBrick, TaskDownloadStoresExactlyTheBlocks) {
  Brick b = make_brick();
  Host host{b};
  EXPECT_EQ(host(req(Op::StartTaskDownload, {0, 2, 6})), (Bytes{0}));
  EXPECT_EQ(host(transfer_payload(1, Bytes{0x14, 0x00, 0x02})), (Bytes{0}));
  EXPECT_EQ(host(transfer_payload(0, Bytes{0x05, 0x00, 0xF6})), (Bytes{0}));
  const auto& task = b.vm.slot(0).tasks[2];
  ASSERT_TRUE(task.has_value());
  EXPECT_EQ(*task, (Bytes{0x14, 0x00, 0x02, 0x05, 0x00, 0xF6}));
}

TEST(LinkBrick, StartDownloadReportsIndexAndMemoryErrors) {
  Brick b = make_brick();
  Host host{b};
  EXPECT_EQ(host(req(Op::StartTaskDownload, {0, 10, 4})), (Bytes{2}));   // task 10: bad index
  EXPECT_EQ(host(req(Op::StartSubroutineDownload, {0, 8, 4})), (Bytes{2}));
  EXPECT_EQ(host(req(Op::StartTaskDownload, {0, 0, 30000})), (Bytes{1}));  // no memory
}

TEST(LinkBrick, TransferWithoutStartIsError6) {
  Brick b = make_brick();
  EXPECT_EQ(ask(b, transfer_payload(1, Bytes{1, 2})), (Bytes{0xBA, 6}));
}

TEST(LinkBrick, OutOfOrderBlocksGetNoReply) {
  Brick b = make_brick();
  Host host{b};
  ASSERT_EQ(host(req(Op::StartTaskDownload, {0, 0, 4})), (Bytes{0}));
  EXPECT_EQ(host(transfer_payload(2, Bytes{1, 2})), std::nullopt);
  EXPECT_EQ(host(transfer_payload(1, Bytes{1, 2})), (Bytes{0}));
  EXPECT_EQ(host(transfer_payload(1, Bytes{3, 4})), std::nullopt);  // 1 again, as a new request
  EXPECT_EQ(host(transfer_payload(2, Bytes{3, 4})), (Bytes{0}));
}

TEST(LinkBrick, BadBlockChecksumIsError3AndTheBlockCanBeSentAgain) {
  Brick b = make_brick();
  Host host{b};
  ASSERT_EQ(host(req(Op::StartTaskDownload, {0, 0, 2})), (Bytes{0}));
  Bytes bad = transfer_payload(1, Bytes{1, 2});
  bad.back() ^= 0x40;
  EXPECT_EQ(host(bad), (Bytes{3}));
  EXPECT_EQ(host(transfer_payload(1, Bytes{1, 2})), (Bytes{0}));
  // The final block's checksum is not checked (seed).
  Bytes last = transfer_payload(0, Bytes{});
  last.back() = 0x99;
  EXPECT_EQ(host(last), (Bytes{0}));
}

TEST(LinkBrick, ARetransmissionIsAnsweredWithoutRunningTwice) {
  Brick b = make_brick();
  Host host{b};
  ASSERT_EQ(host(req(Op::StartTaskDownload, {0, 0, 4})), (Bytes{0}));
  Bytes block = with_toggle(transfer_payload(1, Bytes{0x14, 0x00}), true);
  EXPECT_EQ(ask(b, block), (Bytes{0xB2, 0}));
  EXPECT_EQ(ask(b, block), (Bytes{0xB2, 0}));  // the reply was lost; same form again
  EXPECT_EQ(b.counters.duplicates, 1);
  EXPECT_EQ(ask(b, transfer_payload(0, Bytes{0x02, 0x05})), (Bytes{0xBA, 0}));
  EXPECT_EQ(*b.vm.slot(0).tasks[0], (Bytes{0x14, 0x00, 0x02, 0x05}));  // not 6 bytes
}

// Every host starts its session with Alive in the same form: the second
// session's was counted as a retransmission of the first's.
TEST(LinkBrick, EachSessionsAliveIsANewRequestNotARetransmission) {
  Brick b = make_brick();
  for (int session = 0; session < 3; ++session) {
    Host host{b};  // a new host, in the first toggle form again
    ASSERT_EQ(host(req(Op::Alive)), Bytes{});
  }
  EXPECT_EQ(b.counters.requests, 3);
  EXPECT_EQ(b.counters.duplicates, 0);
  // Any other request repeated in one form still is one.
  Bytes versions = with_toggle(req(Op::GetVersions, {1, 3, 5, 7, 11}), true);
  ASSERT_TRUE(ask(b, versions));
  ASSERT_TRUE(ask(b, versions));
  EXPECT_EQ(b.counters.duplicates, 1);
}

TEST(LinkBrick, DeleteAndProgramRequestsGoToTheMachine) {
  Brick b = make_brick();
  Host host{b};
  ASSERT_EQ(host(req(Op::StartTaskDownload, {0, 1, 1})), (Bytes{0}));
  ASSERT_EQ(host(transfer_payload(0, Bytes{0xF6})), (Bytes{0}));
  ASSERT_TRUE(b.vm.slot(0).tasks[1].has_value());
  EXPECT_EQ(host(req(Op::DeleteTask, {1})), Bytes{});
  EXPECT_FALSE(b.vm.slot(0).tasks[1].has_value());
  EXPECT_EQ(host(req(Op::SetProgramNumber, {3})), Bytes{});
  EXPECT_EQ(b.vm.program(), 3);
}

TEST(LinkBrick, VariablesAndGetValue) {
  Brick b = make_brick();
  Host host{b};
  ASSERT_TRUE(host(req(Op::SetVariable, {5, 2, -1234})));
  auto v = host(req(Op::GetValue, {0, 5}));
  EXPECT_EQ(v, (Bytes{0x2E, 0xFB}));  // -1234 as a little-endian short
}

TEST(LinkBrick, GetValueReadsATimerInTenths) {
  Brick b = make_brick();
  Host host{b};
  b.vm.run_until(2'560 * kMicrosPerMs);
  EXPECT_EQ(host(req(Op::GetValue, {1, 2})), (Bytes{25, 0}));
}

TEST(LinkBrick, SetVariableFromACybermasterSourceStoresZero) {
  Brick b = make_brick();
  Host host{b};
  ASSERT_TRUE(host(req(Op::SetVariable, {4, 2, 77})));
  EXPECT_EQ(host(req(Op::SetVariable, {4, 6, 0})), Bytes{});
  EXPECT_EQ(host(req(Op::GetValue, {0, 4})), (Bytes{0, 0}));
}

TEST(LinkBrick, DatalogUploadsDlrecs) {
  Brick b = make_brick();
  Host host{b};
  ASSERT_EQ(host(req(Op::SetDatalogSize, {3})), (Bytes{0}));
  ASSERT_TRUE(host(req(Op::SetVariable, {2, 2, 300})));
  ASSERT_EQ(host(req(Op::DatalogNext, {0, 2})), (Bytes{0}));
  auto size = host(req(Op::UploadDatalog, {0, 1}));
  // Entry 0: type 0xff, value = entries including itself.
  EXPECT_EQ(size, (Bytes{0xFF, 2, 0}));
  auto entry = host(req(Op::UploadDatalog, {1, 1}));
  EXPECT_EQ(entry, (Bytes{0x02, 0x2C, 0x01}));  // var 2 = 300
  // Out of range: a reply with no records.
  EXPECT_EQ(host(req(Op::UploadDatalog, {1, 5})), Bytes{});
}

TEST(LinkBrick, FirmwareDownloadChecksumAndUnlock) {
  Brick b = make_brick();
  Host host{b};
  // Installed firmware: start firmware download is ignored, no reply.
  EXPECT_EQ(host(req(Op::StartFirmwareDownload, {0x8000, 6, 0})), std::nullopt);
  ASSERT_TRUE(host(req(Op::DeleteFirmware, {1, 3, 5, 7, 11})));
  EXPECT_EQ(host(req(Op::GetVersions, {1, 3, 5, 7, 11})), (Bytes{0, 3, 0, 1, 0, 0, 0, 0}));
  // Without firmware, only the ROM answers: no program requests.
  EXPECT_EQ(host(req(Op::StopAllTasks)), std::nullopt);
  // Checksum announced 6 = 1+2+3.
  EXPECT_EQ(host(req(Op::StartFirmwareDownload, {0x8000, 6, 0})), (Bytes{0}));
  EXPECT_EQ(host(transfer_payload(1, Bytes{1, 2})), (Bytes{0}));
  EXPECT_EQ(host(transfer_payload(0, Bytes{3})), (Bytes{0}));
  auto unlock = host(req(Op::UnlockFirmware, {76, 69, 71, 79, 174}));
  ASSERT_TRUE(unlock);
  EXPECT_EQ(std::string(unlock->begin(), unlock->end()), "Just a bit off the block!");
  EXPECT_TRUE(b.vm.firmware_present());
}

TEST(LinkBrick, FirmwareWithTheWrongChecksumIsError4AndStaysLocked) {
  Brick b = make_brick();
  Host host{b};
  ASSERT_TRUE(host(req(Op::DeleteFirmware, {1, 3, 5, 7, 11})));
  ASSERT_EQ(host(req(Op::StartFirmwareDownload, {0x8000, 7, 0})), (Bytes{0}));
  EXPECT_EQ(host(transfer_payload(0, Bytes{1, 2, 3})), (Bytes{4}));
  ASSERT_TRUE(host(req(Op::UnlockFirmware, {76, 69, 71, 79, 174})));
  EXPECT_FALSE(b.vm.firmware_present());
}

// Delete firmware with a wrong key does nothing (seed: "Otherwise, do
// nothing") and is answered; Unlock firmware with a wrong key is not answered
// and leaves the firmware locked.
TEST(LinkBrick, WrongKeysChangeNothing) {
  Brick b = make_brick();
  Host host{b};
  EXPECT_EQ(host(req(Op::DeleteFirmware, {1, 3, 5, 7, 12})), Bytes{});
  EXPECT_TRUE(b.vm.firmware_present());
  ASSERT_TRUE(host(req(Op::DeleteFirmware, {1, 3, 5, 7, 11})));
  ASSERT_EQ(host(req(Op::StartFirmwareDownload, {0x8000, 3, 0})), (Bytes{0}));
  ASSERT_EQ(host(transfer_payload(0, Bytes{1, 2})), (Bytes{0}));
  EXPECT_EQ(host(req(Op::UnlockFirmware, {76, 69, 71, 79, 175})), std::nullopt);
  EXPECT_FALSE(b.vm.firmware_present());
  EXPECT_TRUE(host(req(Op::UnlockFirmware, {76, 69, 71, 79, 174})));
  EXPECT_TRUE(b.vm.firmware_present());
}

// Delete firmware stops everything: a task download the firmware had open
// is gone with it, and the ROM, which knows only firmware downloads, answers
// a block with 6 (no download started) instead of writing it into the task.
TEST(LinkBrick, DeletingTheFirmwareEndsAnOpenTaskDownload) {
  Brick b = make_brick();
  Host host{b};
  ASSERT_EQ(host(req(Op::StartTaskDownload, {0, 0, 2})), (Bytes{0}));
  ASSERT_TRUE(host(req(Op::DeleteFirmware, {1, 3, 5, 7, 11})));
  EXPECT_EQ(host(transfer_payload(1, Bytes{0x50, 0x50})), (Bytes{6}));
  EXPECT_EQ(*b.vm.slot(b.vm.program()).tasks[0], (Bytes{0, 0}));
}

TEST(LinkBrick, FirmwareBlockChecksumErrorAdvancesTheSequence) {
  // The ROM bug of the seed: after error 3 the host must number the resent
  // block one higher.
  Brick b = make_brick();
  Host host{b};
  ASSERT_TRUE(host(req(Op::DeleteFirmware, {1, 3, 5, 7, 11})));
  ASSERT_TRUE(host(req(Op::StartFirmwareDownload, {0x8000, 3, 0})));
  Bytes bad = transfer_payload(1, Bytes{1});
  bad.back() = 0x55;
  EXPECT_EQ(host(bad), (Bytes{3}));
  EXPECT_EQ(host(transfer_payload(1, Bytes{1})), std::nullopt);  // out of order now
  EXPECT_EQ(host(transfer_payload(2, Bytes{1})), (Bytes{0}));
}

TEST(LinkBrick, HearDecodesFramesAndRepliesFramed) {
  Brick b = make_brick();
  Bytes in{0x00, 0x13};  // noise first
  Bytes f = frame(Bytes{0x10});
  in.insert(in.end(), f.begin(), f.end());
  EXPECT_EQ(hear(b, in), frame(Bytes{0xEF}));
  EXPECT_EQ(b.counters.rejected, 1);
}

TEST(LinkBrick, NoiseLosesOrFlipsAboutTheRequestedShare) {
  Noise none = make_noise(0.0, 1);
  Bytes data(10000, 0xA5);
  EXPECT_EQ(apply_noise(none, data), data);
  Noise some = make_noise(0.05, 7);
  Bytes out = apply_noise(some, data);
  int changed = static_cast<int>(data.size() - out.size());
  for (auto v : out) changed += v != 0xA5;
  EXPECT_GT(changed, 350);  // 5% of 10000 = 500, within a wide margin
  EXPECT_LT(changed, 650);
}

}  // namespace
}  // namespace rcx

namespace rcx {
namespace {

// Every request of the seed gets its reply (with the reply layout of the
// table) when its arguments are valid; Set message is the one without.
TEST(LinkBrickAll, EveryRequestIsAnswered) {
  struct Case {
    Op op;
    std::vector<int> values;
  };
  const std::vector<Case> cases = {
      {Op::AbsoluteValue, {1, 2, -5}}, {Op::Alive, {}}, {Op::AddToVariable, {1, 2, 5}},
      {Op::AndVariable, {1, 2, 3}}, {Op::ClearSensorValue, {0}}, {Op::ClearTimer, {1}},
      {Op::DeleteAllSubroutines, {}}, {Op::DeleteAllTasks, {}}, {Op::DatalogNext, {0, 1}},
      {Op::DeleteSubroutine, {2}}, {Op::DeleteTask, {3}}, {Op::DivideVariable, {1, 2, 2}},
      {Op::GetMemoryMap, {}}, {Op::GetBatteryPower, {}}, {Op::GetValue, {9, 0}},
      {Op::GetVersions, {1, 3, 5, 7, 11}}, {Op::MultiplyVariable, {1, 2, 3}}, {Op::OrVariable, {1, 2, 8}},
      {Op::PlaySound, {2}}, {Op::PlayTone, {440, 50}}, {Op::SetDatalogSize, {10}}, {Op::SetDisplay, {2, 1}},
      {Op::SetMotorOnOff, {0x81}}, {Op::SetMotorDirection, {0x82}}, {Op::SetMotorPower, {0x07, 2, 3}},
      {Op::SetPowerDownDelay, {10}}, {Op::SetProgramNumber, {1}}, {Op::SetSensorMode, {0, 0x20}},
      {Op::SetSensorType, {1, 1}}, {Op::SetTime, {10, 30}}, {Op::SetTransmitterRange, {1}},
      {Op::SetVariable, {1, 2, 9}}, {Op::SignVariable, {1, 2, -9}}, {Op::StartTaskDownload, {0, 0, 2}},
      {Op::TransferData, {}}, {Op::StartSubroutineDownload, {0, 1, 2}}, {Op::StopAllTasks, {}},
      {Op::StartTask, {0}}, {Op::StopTask, {0}}, {Op::SubtractFromVariable, {1, 2, 1}},
      {Op::UploadDatalog, {0, 1}}, {Op::PowerOff, {}},
  };
  Brick b = make_brick();
  bool toggle = false;
  std::set<Op> covered;
  for (const auto& c : cases) {
    Bytes request = c.op == Op::TransferData ? transfer_payload(0, Bytes{0xF6, 0xF6})
                                             : request_payload(info(c.op), c.values);
    request = with_toggle(request, toggle);
    toggle = !toggle;
    auto reply = answer(b, request);
    ASSERT_TRUE(reply.has_value()) << info(c.op).name << ": " << (b.log.empty() ? "" : b.log.back());
    EXPECT_TRUE(answers(*reply, request)) << info(c.op).name;
    auto size = reply_size(request);
    ASSERT_TRUE(std::holds_alternative<int>(size));
    EXPECT_EQ(static_cast<int>(reply->size()), std::get<int>(size)) << info(c.op).name;
    covered.insert(c.op);
  }
  // Firmware requests are covered by the firmware tests; Set message has no reply.
  for (const auto& op : opcodes()) {
    if (op.is_request() && op.replies && !covered.count(op.op)) {
      EXPECT_TRUE(op.op == Op::DeleteFirmware || op.op == Op::StartFirmwareDownload || op.op == Op::UnlockFirmware)
          << op.name << " is not covered";
    }
  }
  // Their effects reached the machine.
  EXPECT_EQ(b.vm.state().transmitter_range, 1);
  EXPECT_EQ(b.vm.state().power_down_minutes, 10);
  EXPECT_EQ(b.vm.clock_minutes(), 10 * 60 + 30);
  EXPECT_EQ(b.vm.program(), 1);
  EXPECT_EQ(b.vm.stop().kind, StopKind::PowerOff);
  // Powered off: silence.
  EXPECT_EQ(answer(b, Bytes{0x18}), std::nullopt);
}

}  // namespace
}  // namespace rcx
