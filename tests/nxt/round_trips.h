// A round trip for every command of the table, shared by the in-process
// test (virtual_nxt_test) and the one over a pseudo-terminal (transport_test).
// The client must talk to a fresh virtual NXT; afterwards its name is "Robo"
// and its flash is empty (SetBrickName, DeleteUserFlash ran last).
#pragma once

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "nxt/client.h"

namespace nxt::test {

using V = std::vector<Value>;
inline Value n(std::int64_t v) { return v; }
inline Value s(std::string v) { return v; }

// One request per command, with the status a fresh brick (with a program
// "prog.rxe" running and a file "a.txt") answers.
struct Trip {
  V values;
  std::uint8_t status;
};

inline void every_command_round_trip(Client& client) {
  ASSERT_FALSE(upload_file(client, "a.txt", Bytes{'a', 'b', 'c'}));
  ASSERT_FALSE(upload_file(client, "s.rso", Bytes(4, 0)));
  ASSERT_FALSE(upload_file(client, "prog.rxe", Bytes(10, 1)));
  ASSERT_TRUE(std::holds_alternative<Decoded>(call_ok(client, "StartProgram", std::vector<Value>{std::string("prog.rxe")})));
  const std::map<std::string_view, Trip> trips = {
      {"StartProgram", {{s("prog.rxe")}, 0}},
      {"StopProgram", {{}, 0}},
      {"PlaySoundFile", {{n(0), s("s.rso")}, 0}},
      {"PlayTone", {{n(440), n(200)}, 0}},
      {"SetOutputState", {{n(1), n(50), n(1), n(0), n(0), n(0x20), n(0)}, 0}},
      {"SetInputMode", {{n(0), n(1), n(0x20)}, 0}},
      {"GetOutputState", {{n(1)}, 0}},
      {"GetInputValues", {{n(0)}, 0}},
      {"ResetInputScaledValue", {{n(0)}, 0}},
      {"MessageWrite", {{n(0), n(0), Bytes{'x', 0}}, status::kNoProgram}},  // StopProgram ran before it
      {"ResetMotorPosition", {{n(0), n(0)}, 0}},
      {"GetBatteryLevel", {{}, 0}},
      {"StopSoundPlayback", {{}, 0}},
      {"KeepAlive", {{}, 0}},
      // Port 1 is SWITCH (SetInputMode above): the firmware's LS status check says 0xE0.
      {"LSGetStatus", {{n(0)}, status::kChannelBusy}},
      {"LSWrite", {{n(0), n(2), n(1), Bytes{2, 0x42}}, status::kChannelBusy}},  // port 1 is not LOWSPEED
      {"LSRead", {{n(0)}, status::kChannelBusy}},
      {"GetCurrentProgramName", {{}, status::kNoProgram}},
      {"MessageRead", {{n(0), n(0), n(1)}, status::kNoProgram}},
      {"GetButtonState", {{}, status::kUnknownCommand}},
      {"DatalogRead", {{n(0)}, 0}},
      {"DatalogSetTimes", {{n(5)}, 0}},
      {"BTGetContactCount", {{}, 0}},
      {"BTGetContactName", {{n(0)}, 0}},
      {"BTGetConnCount", {{}, 0}},
      {"BTGetConnName", {{n(0)}, 0}},
      {"SetProperty", {{n(1), Bytes{2}}, 0}},
      {"GetProperty", {{n(1)}, 0}},
      {"UpdateResetCount", {{n(0)}, 0}},
      {"OpenRead", {{s("a.txt")}, 0}},
      {"OpenWrite", {{s("b.txt"), n(3)}, 0}},
      {"Read", {{n(0), n(3)}, 0}},
      {"Write", {{n(1), Bytes{1, 2, 3}}, 0}},
      {"Close", {{n(1)}, 0}},
      {"Delete", {{s("b.txt")}, 0}},
      {"FindFirst", {{s("*.txt")}, 0}},
      {"FindNext", {{n(1)}, status::kFileNotFound}},  // a.txt was the only match
      {"GetFirmwareVersion", {{}, 0}},
      {"OpenWriteLinear", {{s("c.rxe"), n(1)}, 0}},
      {"OpenWriteData", {{s("d.dat"), n(8)}, 0}},
      {"OpenAppendData", {{s("a.txt")}, status::kAppendNotPossible}},
      {"FindFirstModule", {{s("*.mod")}, 0}},
      {"FindNextModule", {{n(0)}, 0}},  // the one module search, handle 0
      {"CloseModuleHandle", {{n(0)}, 0}},
      {"ReadIOMap", {{n(0x000C0001), n(0), n(4)}, 0}},
      {"WriteIOMap", {{n(0x000C0001), n(0), n(2), Bytes{1, 2}}, 0}},
      {"Boot", {{s("Let's dance: SAMBA")}, status::kUndefined}},  // as on any link but USB
      {"SetBrickName", {{s("Robo")}, 0}},
      {"GetDeviceInfo", {{}, 0}},
      {"PollCommandLength", {{n(0)}, 0}},
      {"PollCommand", {{n(0), n(10)}, 0}},
      {"DeleteUserFlash", {{}, 0}},
  };
  // In the table's order, so handles and program state evolve as written.
  std::set<std::string_view> done;
  for (const auto& c : commands()) {
    auto it = trips.find(c.name);
    ASSERT_NE(it, trips.end()) << c.name << " has no round trip";
    auto r = call(client, c, it->second.values);
    ASSERT_TRUE(std::holds_alternative<Decoded>(r)) << c.name << ": " << std::get<CallError>(r).message;
    const auto& d = std::get<Decoded>(r);
    EXPECT_EQ(d.command, &c) << c.name;
    EXPECT_EQ(d.status, it->second.status) << c.name << ": " << describe(d);
    done.insert(c.name);
  }
  EXPECT_EQ(done.size(), trips.size());
}


}  // namespace nxt::test
