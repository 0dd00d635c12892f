// nqc runs under a time and memory limit (issue 21): a macro bomb made it
// take 7 GB and never return. Fake nqc scripts stand in for the real one.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "verify/external_nqc.h"

using namespace rcx::semtest;

namespace {

struct FakeNqc {
  std::filesystem::path dir = std::filesystem::temp_directory_path() /
                              ("rcxc-fake-nqc-" + std::to_string(::getpid()) + "-" +
                               ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::string script, source;
  explicit FakeNqc(const std::string& body) {
    std::filesystem::create_directories(dir);
    script = (dir / "nqc").string();
    std::ofstream(script) << "#!/bin/sh\n" << body << "\n";
    ::chmod(script.c_str(), 0755);
    source = (dir / "p.nqc").string();
    std::ofstream(source) << "task main() {}\n";
  }
  ~FakeNqc() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

}  // namespace

TEST(NqcLimits, AnNqcThatNeverEndsIsKilled) {
  FakeNqc fake("exec sleep 600");
  auto start = std::chrono::steady_clock::now();
  auto r = compile_with_nqc(fake.script, fake.source, {}, NqcLimits{1, 512});
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(30));  // a hang guard
  EXPECT_FALSE(r.image);
  EXPECT_EQ(r.failure, "nqc did not finish within 1 s and was stopped");
}

// An AddressSanitizer build leaves the address-space limit off
// (verify/external_nqc.cpp: its stand-ins for nqc reserve terabytes), so
// there the memory limit is "unlimited"; the time limit stays.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

TEST(NqcLimits, NqcRunsUnderTheMemoryLimit) {
  // The script prints its own limits as nqc's "log".
  FakeNqc fake("echo \"as $(ulimit -v) cpu $(ulimit -t)\"; exit 1");
  auto r = compile_with_nqc(fake.script, fake.source, {}, NqcLimits{7, 256});
  const std::string as = kAddressSanitizer ? "unlimited" : "262144";
  EXPECT_TRUE(r.failure.ends_with("; it printed:\nas " + as + " cpu 7\n")) << r.failure;
}

TEST(NqcLimits, AMissingNqcIsSaidSo) {
  auto r = compile_with_nqc("/no/such/nqc", "p.nqc");
  EXPECT_EQ(r.failure, "cannot run '/no/such/nqc' (is nqc installed?)");
}

// What a failing nqc printed went to the terminal raw: an escape sequence in
// it could clear the screen or retitle the window.
TEST(NqcLimits, WhatAFailingNqcPrintedIsShownWithoutControlBytes) {
  FakeNqc fake("printf 'bad\\033[2J\\007\\tend\\n'; exit 1");
  auto r = compile_with_nqc(fake.script, fake.source, {}, NqcLimits{7, 256});
  EXPECT_TRUE(r.failure.ends_with("; it printed:\nbad\\x1b[2J\\x07\tend\n")) << r.failure;
}

// `rcxc compare --nqc-path /bin/false` said "nqc failed: " and nothing more.
TEST(NqcLimits, AnNqcThatFailsSilentlyIsSaidSoWithItsExitStatusAndCommand) {
  FakeNqc fake("exit 3");
  auto r = compile_with_nqc(fake.script, fake.source, {"-DX=a b"}, NqcLimits{7, 256});
  EXPECT_FALSE(r.image);
  EXPECT_TRUE(r.failure.starts_with("nqc failed with exit status 3 and printed nothing (the command was: " + fake.script +
                                    " -Trcx -I" + fake.dir.string() + " -O"))
      << r.failure;
  EXPECT_TRUE(r.failure.ends_with("/out.rcx '-DX=a b' " + fake.source + ")")) << r.failure;
}

TEST(NqcLimits, WhatAFailingNqcPrintedComesWithItsExitStatus) {
  FakeNqc fake("echo 'something odd'; exit 4");
  auto r = compile_with_nqc(fake.script, fake.source, {}, NqcLimits{7, 256});
  EXPECT_TRUE(r.failure.starts_with("nqc failed with exit status 4 and printed no message in nqc's form (the command "
                                    "was: " + fake.script))
      << r.failure;
  EXPECT_TRUE(r.failure.ends_with("; it printed:\nsomething odd\n")) << r.failure;
}

// What a failing nqc printed is shown up to 64 KiB, and ended mid-word
// there ("erro") as if that were all: the cut is said.
TEST(NqcLimits, WhatAFailingNqcPrintedPastTheCapIsSaidToBeCut) {
  FakeNqc fake("yes error | head -c 100000; exit 1");
  auto r = compile_with_nqc(fake.script, fake.source, {}, NqcLimits{7, 256});
  EXPECT_TRUE(r.failure.ends_with("\n[... cut: nqc printed more than 64 KiB]")) << r.failure.substr(0, 300);
  FakeNqc exact("yes error | head -c 65536; exit 1");  // 64 KiB exactly: all of it shown, nothing cut
  auto whole = compile_with_nqc(exact.script, exact.source, {}, NqcLimits{7, 256});
  EXPECT_EQ(whole.failure.find("cut:"), std::string::npos);
  EXPECT_TRUE(whole.failure.ends_with("error\nerror\nerro")) << whole.failure.substr(whole.failure.size() - 40);
}
