// Host-side operations the IR link maps requests onto: downloads with the
// seed's error codes, the 94-entry memory map, datalog size/upload, direct
// commands with their reply payloads.
#include <gtest/gtest.h>

#include "runtime/vm.h"
#include "tests/runtime/vm_support.h"

using namespace vmtest;
using rcx::DownloadStatus;
using rcx::kMemoryBase;
using rcx::kMicrosPerMs;

TEST(VmHost, DownloadErrorCodes) {
  rcx::Machine m;
  EXPECT_EQ(m.begin_task_download(10, 5), DownloadStatus::BadIndex);
  EXPECT_EQ(m.begin_sub_download(8, 5), DownloadStatus::BadIndex);
  EXPECT_EQ(m.begin_task_download(0, rcx::kMemoryBytes), DownloadStatus::NoMemory);  // the datalog size entry uses 3
  EXPECT_EQ(m.begin_task_download(0, rcx::kMemoryBytes - 3), DownloadStatus::Ok);
  EXPECT_EQ(m.free_memory(), 0);
  EXPECT_EQ(m.begin_sub_download(0, 0), DownloadStatus::NoMemory);  // the appended return needs a byte
  EXPECT_EQ(m.begin_task_download(0, 10), DownloadStatus::Ok);      // replacing frees the old space
  EXPECT_EQ(m.free_memory(), rcx::kMemoryBytes - 3 - 10);
}

TEST(VmHost, DownloadThenRun) {
  rcx::Machine m(ms_config());
  Bytes task = code({set(0, 42), call(2)});
  Bytes sub = set(1, 7);
  ASSERT_EQ(m.begin_sub_download(2, static_cast<int>(sub.size())), DownloadStatus::Ok);
  ASSERT_TRUE(m.write_download(sub));
  m.end_download();
  ASSERT_EQ(m.begin_task_download(0, static_cast<int>(task.size())), DownloadStatus::Ok);
  ASSERT_TRUE(m.write_download(std::span(task).first(3)));  // in two blocks
  ASSERT_TRUE(m.write_download(std::span(task).subspan(3)));
  m.end_download();
  EXPECT_FALSE(m.write_download(task));  // no download open
  m.start_task(0);
  m.run(1000 * kMicrosPerMs);
  EXPECT_EQ(var(m, 0), 42);
  EXPECT_EQ(var(m, 1), 7);
}

TEST(VmHost, MemoryMapLayout) {
  rcx::Machine m;
  ASSERT_FALSE(m.load(0, image({{0, Bytes(10, 0x50)}, {1, Bytes(4, 0x50)}}, {{0, Bytes(5, 0xf6)}})));
  ASSERT_FALSE(m.load(1, image({{0, Bytes(7, 0x50)}})));
  auto map = m.memory_map();
  EXPECT_EQ(map[0], kMemoryBase);                 // program 0 sub 0
  EXPECT_EQ(map[1], kMemoryBase + 6);             // 5 bytes + appended return
  EXPECT_EQ(map[39], kMemoryBase + 6);
  EXPECT_EQ(map[40], kMemoryBase + 6);            // program 0 task 0
  EXPECT_EQ(map[41], kMemoryBase + 16);           // task 1
  EXPECT_EQ(map[42], kMemoryBase + 20);
  EXPECT_EQ(map[50], kMemoryBase + 20);           // program 1 task 0
  EXPECT_EQ(map[90], kMemoryBase + 27);           // first datalog address
  EXPECT_EQ(map[91], kMemoryBase + 30);           // after the size entry
  EXPECT_EQ(map[92], kMemoryBase + 30);           // first free
  EXPECT_EQ(map[93], kMemoryBase + rcx::kMemoryBytes - 1);
  ASSERT_TRUE(m.set_datalog_size(10));
  map = m.memory_map();
  EXPECT_EQ(map[92], kMemoryBase + 27 + 11 * 3);
}

TEST(VmHost, LoadRefusesWhatDoesNotFit) {
  rcx::Machine m;
  auto error = m.load(0, image({{0, Bytes(static_cast<std::size_t>(rcx::kMemoryBytes), 0)}}));
  ASSERT_TRUE(error);
  EXPECT_NE(error->find("insufficient memory"), std::string::npos);
  EXPECT_FALSE(m.slot(0).tasks[0].has_value());
}

TEST(VmHost, DatalogSizeAndUpload) {
  rcx::Machine m;
  EXPECT_FALSE(m.set_datalog_size(rcx::kMemoryBytes / 3));  // plus the size entry: too big
  ASSERT_TRUE(m.set_datalog_size(2));
  auto none = m.upload_datalog(0, 1);
  ASSERT_EQ(none.size(), 1u);
  EXPECT_EQ(none[0].type, 0xff);
  EXPECT_EQ(none[0].value, 1);  // the size entry counts itself
  auto r = m.execute_direct(Bytes{0x14, 3, 2, 0x39, 0x30});  // var3 = 12345
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(m.execute_direct(Bytes{0x62, 0, 3}).payload, Bytes{0});
  EXPECT_EQ(m.execute_direct(Bytes{0x6a, 0, 3}).payload, Bytes{0});  // toggle form
  EXPECT_EQ(m.execute_direct(Bytes{0x62, 0, 3}).payload, Bytes{1});  // full
  auto log = m.upload_datalog(0, 3);
  ASSERT_EQ(log.size(), 3u);
  EXPECT_EQ(log[0].value, 3);
  EXPECT_EQ(log[1].type, 3);
  EXPECT_EQ(log[1].value, 12345);
  EXPECT_TRUE(m.upload_datalog(1, 3).empty());  // past the end: an error
  EXPECT_EQ(m.execute_direct(Bytes{0xa4, 1, 0, 1, 0}).payload, (Bytes{0x03, 0x39, 0x30}));
  EXPECT_EQ(m.execute_direct(Bytes{0x52, 0x00, 0x10}).payload, Bytes{1});  // 4096 entries: no memory
}

TEST(VmHost, DirectGetValueBatteryVersionsMemoryMap) {
  rcx::Machine m;
  ASSERT_TRUE(m.execute_direct(Bytes{0x14, 0, 2, 0x34, 0x12}).ok);
  EXPECT_EQ(m.execute_direct(Bytes{0x12, 0, 0}).payload, (Bytes{0x34, 0x12}));
  EXPECT_EQ(m.execute_direct(Bytes{0x1a, 0, 0}).payload, (Bytes{0x34, 0x12}));
  EXPECT_FALSE(m.execute_direct(Bytes{0x12, 2, 0}).ok);  // immediate is not allowed for Get value
  EXPECT_EQ(m.execute_direct(Bytes{0x30}).payload, (Bytes{0x54, 0x24}));  // 9300 mV
  m.set_battery_mv(7000);
  EXPECT_EQ(m.battery_mv(), 7000);
  EXPECT_EQ(m.execute_direct(Bytes{0x15, 1, 3, 5, 7, 11}).payload, (Bytes{0, 3, 0, 1, 0, 3, 0, 9}));
  EXPECT_FALSE(m.execute_direct(Bytes{0x15, 1, 3, 5, 7, 12}).ok);  // wrong key: no reply
  auto map = m.execute_direct(Bytes{0x20}).payload;
  ASSERT_EQ(map.size(), 188u);
  EXPECT_EQ(map[0], kMemoryBase >> 8);  // big endian
  EXPECT_EQ(map[1], kMemoryBase & 0xff);
  EXPECT_TRUE(m.execute_direct(Bytes{0x10}).ok);
  EXPECT_TRUE(m.execute_direct(Bytes{0x10}).payload.empty());
}

TEST(VmHost, DirectCommandsActOnTheBrick) {
  rcx::Machine m;
  ASSERT_TRUE(m.execute_direct(Bytes{0x21, 0x81}).ok);
  EXPECT_EQ(m.state().outputs[0].mode, rcx::OutputMode::On);
  ASSERT_TRUE(m.execute_direct(Bytes{0x59, 3}).ok);
  ASSERT_EQ(events_of(m, rcx::EventKind::Sound).size(), 1u);
  ASSERT_TRUE(m.execute_direct(Bytes{0xf7, 77}).ok);
  EXPECT_EQ(m.state().message, 77);
  ASSERT_TRUE(m.execute_direct(Bytes{0x31, 1}).ok);
  EXPECT_EQ(m.state().transmitter_range, 1);
  ASSERT_TRUE(m.execute_direct(Bytes{0x31, 5}).ok);
  EXPECT_EQ(m.state().transmitter_range, 1);  // other values ignored
}

TEST(VmHost, DirectRefusesWhatIsNotARequestOrIsMalformed) {
  rcx::Machine m;
  EXPECT_FALSE(m.execute_direct(Bytes{}).ok);
  EXPECT_FALSE(m.execute_direct(Bytes{0x27, 0x00}).ok);        // branch: a command only
  EXPECT_FALSE(m.execute_direct(Bytes{0x14, 0}).ok);           // too short
  EXPECT_FALSE(m.execute_direct(Bytes{0x45, 1, 0, 0, 0, 0}).ok);  // transfer data: download interface
}

TEST(VmHost, StartStopTasksFromTheHost) {
  rcx::Machine m(ms_config());
  m.load(0, image({{0, code({wait(100), set(0, 1)})}, {3, code({wait(100), set(1, 1)})}}));
  ASSERT_TRUE(m.execute_direct(Bytes{0x71, 3}).ok);
  m.start_task(0);
  m.run_until(10 * kMicrosPerMs);
  m.stop_task(0);
  m.run(5000 * kMicrosPerMs);
  EXPECT_EQ(var(m, 0), 0);
  EXPECT_EQ(var(m, 1), 1);
}

TEST(VmHost, DeleteAllTasksAndSubs) {
  rcx::Machine m;
  m.load(0, image({{0, Bytes{0x50}}, {1, Bytes{0x50}}}, {{0, Bytes{0x50}}}));
  ASSERT_TRUE(m.execute_direct(Bytes{0x70}).ok);
  EXPECT_FALSE(m.slot(0).subs[0].has_value());
  EXPECT_TRUE(m.slot(0).tasks[0].has_value());
  ASSERT_TRUE(m.execute_direct(Bytes{0x40}).ok);
  EXPECT_FALSE(m.slot(0).tasks[1].has_value());
  EXPECT_EQ(m.free_memory(), rcx::kMemoryBytes - 3);
}

TEST(VmHost, PowerOffAndFirmware) {
  rcx::Machine m;
  ASSERT_TRUE(m.execute_direct(Bytes{0xb1, 0}).ok);
  m.power_off();
  EXPECT_EQ(m.stop().kind, rcx::StopKind::Running);  // delay 0: ignored
  m.set_power_down_delay(5);
  m.power_off();
  EXPECT_EQ(m.stop().kind, rcx::StopKind::PowerOff);
  EXPECT_TRUE(m.firmware_present());
  ASSERT_TRUE(m.execute_direct(Bytes{0x65, 1, 3, 5, 7, 11}).ok);
  EXPECT_FALSE(m.firmware_present());
  EXPECT_EQ(m.execute_direct(Bytes{0x15, 1, 3, 5, 7, 11}).payload, (Bytes{0, 3, 0, 1, 0, 0, 0, 0}));
}
