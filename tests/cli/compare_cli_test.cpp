// `rcxc compare` end to end, with a stand-in for nqc (--nqc-path) that writes
// an image of our choosing, so both "same" and a real difference are known.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <string>
#include <utility>

#include "rcx/image.h"
#include "tests/support/process.h"

using rcxc::test::run_rcxc;
using rcxc::test::TempDir;

namespace {

// A fake nqc: copies IMAGE to the file named by its -O option.
std::string fake_nqc(const TempDir& d, const std::string& image) {
  std::string script = d.write("fake-nqc",
                               "#!/bin/sh\n"
                               "for a in \"$@\"; do case \"$a\" in -O*) cp '" + image + "' \"${a#-O}\";; esac; done\n");
  chmod(script.c_str(), 0755);
  return script;
}

// task main: touch on input 1; wait for a press; play `sound`.
std::string image_playing(const TempDir& d, int sound) {
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0,
                           {0x13, 0x07, 0x02, 0x07, 0xe1, 0x87,                // startup: pwr ABC 7, dir ABC fwd
                            0x32, 0x00, 0x01, 0x42, 0x00, 0x20,                // touch sensor, boolean mode
                            0x85, 0x82, 0x09, 0x01, 0x00, 0x00, 0xfa,          // chk 1 != sensor 0, back to itself
                            0x51, static_cast<std::uint8_t>(sound)}});         // play sound
  img.symbols.push_back({rcx::SymbolType::Task, 0, "main"});
  return d.write("fake.rcx", rcx::write_image(img));
}

constexpr const char* kSource =
    "task main() { SetSensor(SENSOR_1, SENSOR_TOUCH); until (SENSOR_1 == 1); PlaySound(SOUND_UP); }\n";

// A stand-in for nqc that compiles with rcxc -O0: compare then judges -O0
// code against -Os code, whose instruction counts differ.
std::string rcxc_o0_as_nqc(const TempDir& d) {
  std::string script = d.write("o0-nqc",
                               "#!/bin/sh\n"
                               "for a in \"$@\"; do case \"$a\" in -Trcx) ;; -I*) i=\"${a#-I}\";; -O*) o=\"${a#-O}\";; "
                               "*) f=\"$a\";; esac; done\n"
                               "exec '" RCXC_BINARY "' compile -O0 -I \"$i\" -o \"$o\" \"$f\"\n");
  chmod(script.c_str(), 0755);
  return script;
}

}  // namespace

TEST(CompareCli, SameBehaviourIsSame) {
  TempDir d;
  auto r = run_rcxc({"compare", d.write("p.nqc", kSource), "--nqc-path", fake_nqc(d, image_playing(d, 3))});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(r.out.find("DIFFERENT"), std::string::npos) << r.out;
}

// Against -O0 code (three arithmetic steps on a local before the motor
// commands), rcxc's code computes the power at compile time and switches
// A on sooner: each scenario's line says by how much.
TEST(CompareCli, SameLinesSayHowMuchSoonerRcxcActed) {
  TempDir d;
  std::string src = d.write("p.nqc", "task main() { int x = 1; x += 2; x *= 2; SetPower(OUT_A, x); On(OUT_A); }\n");
  auto r = run_rcxc({"compare", src, "--nqc-path", rcxc_o0_as_nqc(d)});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("timing over 1 matched event: rcxc's code acted"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("instructions sooner on average"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("later"), std::string::npos) << r.out;
}

TEST(CompareCli, ADifferentSoundIsADifferenceNoInputShiftCanHide) {
  TempDir d;
  auto r = run_rcxc({"compare", d.write("p.nqc", kSource), "--nqc-path", fake_nqc(d, image_playing(d, 2))});
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("DIFFERENT"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("sound 3"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("sound 2"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" | "), std::string::npos) << r.out;  // side by side
}

TEST(CompareCli, MissingNqcIsNotComparable) {
  TempDir d;
  auto r = run_rcxc({"compare", d.write("p.nqc", kSource), "--nqc-path", "/no/such/nqc"});
  EXPECT_EQ(r.exit_code, 5) << r.out << r.err;
}

TEST(CompareCli, TheStandardInputIsRefusedSinceNqcReadsTheFileToo) {
  auto r = run_rcxc({"compare", "-"}, kSource);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("compare needs the program in a file"), std::string::npos) << r.err;
}

// The test's own harness: a program that exits without reading its input
// leaves the input's writer with a closed pipe. The write must fail, not
// kill the test with SIGPIPE (the test above died so under load, when
// rcxc had refused '-' before the input was written).
TEST(CompareCli, InputLeftUnreadKillsNoTest) {
  auto r = rcxc::test::run_process({"/bin/true"}, std::string(4 << 20, 'x'));
  EXPECT_EQ(r.exit_code, 0);
}

// A missing file, a folder or binary bytes went to nqc first, whose refusal
// read "nqc does not compile this program; nothing to compare" (exit 5), or
// as a binary file "is an .rcx image". They are bad inputs, said as rcxc
// compile says them, before any nqc runs (the fake one would accept all).
TEST(CompareCli, AFileThatIsNoSourceIsABadInputNotNothingToCompare) {
  TempDir d;
  std::string nqc = fake_nqc(d, image_playing(d, 3));
  const std::pair<std::string, std::string> cases[] = {
      {d.path + "/missing.nqc", "cannot open"},
      {d.path, "is a directory, not a source file"},
      {d.write("bin.nqc", std::string("\x01\x00\xff\x00", 4)), "is not NQC source: it holds binary data"},
  };
  for (const auto& [file, message] : cases) {
    auto r = run_rcxc({"compare", file, "--nqc-path", nqc});
    EXPECT_EQ(r.exit_code, 1) << file << ": " << r.out << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << file << ": " << r.err;
    EXPECT_EQ(r.out.find("nothing to compare"), std::string::npos) << file << ": " << r.out;
  }
  // A file whose reading fails (EIO at offset 0) was taken for source and,
  // as neither compiler read it, was "nothing to compare" (exit 5).
  auto unreadable = run_rcxc({"compare", "/proc/self/mem"});
  EXPECT_EQ(unreadable.exit_code, 1) << unreadable.out << unreadable.err;
  EXPECT_NE(unreadable.err.find("could not be read"), std::string::npos) << unreadable.err;
  EXPECT_EQ(unreadable.out.find("nothing to compare"), std::string::npos) << unreadable.out;
}

// A program nqc refuses got one line, "nqc does not compile this program",
// and nothing about why, even when rcxc refused it too. Both compilers'
// messages are shown now, and the line says which refused.
TEST(CompareCli, AProgramNqcRefusesShowsWhy) {
  TempDir d;
  std::string refusing = d.write("refusing-nqc", "#!/bin/sh\necho '# Error: no such thing'\n"
                                                 "echo 'File \"p.nqc\" ; line 1'\nexit 1\n");
  chmod(refusing.c_str(), 0755);
  auto both = run_rcxc({"compare", d.write("p.nqc", "task main() { nope(); }\n"), "--nqc-path", refusing});
  EXPECT_EQ(both.exit_code, 5) << both.out << both.err;
  EXPECT_NE(both.out.find("neither nqc nor rcxc compiles this program"), std::string::npos) << both.out;
  EXPECT_NE(both.err.find("error: 'nope' is not declared"), std::string::npos) << both.err;
  EXPECT_NE(both.err.find("nqc: line 1: no such thing"), std::string::npos) << both.err;
  auto only_nqc = run_rcxc({"compare", d.write("q.nqc", kSource), "--nqc-path", refusing});
  EXPECT_EQ(only_nqc.exit_code, 5) << only_nqc.out << only_nqc.err;
  EXPECT_NE(only_nqc.out.find("nqc does not compile this program"), std::string::npos) << only_nqc.out;
  EXPECT_NE(only_nqc.err.find("nqc: line 1: no such thing"), std::string::npos) << only_nqc.err;
}

TEST(CompareCli, ProgramRcxcRejectsButNqcAcceptsFails) {
  TempDir d;
  auto r = run_rcxc({"compare", d.write("p.nqc", "task main() { nope(); }\n"), "--nqc-path",
                     fake_nqc(d, image_playing(d, 3))});
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("nqc compiles this program but rcxc does not"), std::string::npos) << r.out;
}

// --for took any positive number, and --for times 1000 (microseconds)
// overflowed a signed 64-bit value: undefined behaviour, in practice a run
// that ended at once and compared nothing. It has run's limit now.
TEST(CompareCli, ForBeyondTheClockIsAUsageError) {
  TempDir d;
  auto r = run_rcxc({"compare", d.write("p.nqc", kSource), "--for", "9223372036854775807"});
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("--for"), std::string::npos) << r.err;
}

// A task polls one light sensor four times per round and answers each
// reading with a half-second pulse (a robot sniffing for light, as a 2011
// blog program did). In the built-in light scenario a reading starts a pulse
// that is still running when the next inputs (rotation sensors the program
// never reads) arrive. Placing each input only up to the next one let the
// first check that happened to agree stand, and the runs then parted at the
// second pulse: compare said DIFFERENT for two correct builds.
TEST(CompareCli, AReactionOutlastingTheNextInputIsStillInstructionTiming) {
  TempDir d;
  const std::string program =
      "sub go() { OnRev(OUT_C); OnFwd(OUT_A); }\n"
      "sub halt() { Off(OUT_A + OUT_C); }\n"
      "task sniff() {\n"
      "  while (true) {\n"
      "    if (SENSOR_2 < 700) { go(); Wait(25); halt(); Wait(25); }\n"
      "    if (SENSOR_2 < 700) { OnFwd(OUT_A); Wait(25); halt(); Wait(25); }\n"
      "    if (SENSOR_2 < 700) { go(); Wait(25); halt(); Wait(25); }\n"
      "    if (SENSOR_2 < 700) { OnRev(OUT_C); Wait(25); halt(); Wait(25); }\n"
      "  }\n"
      "}\n"
      "task main() {\n"
      "  SetSensorType(SENSOR_2, SENSOR_TYPE_LIGHT);\n"
      "  SetSensorMode(SENSOR_2, SENSOR_MODE_RAW);\n"
      "  start sniff;\n"
      "}\n";
  auto r = run_rcxc({"compare", d.write("sniff.nqc", program), "--nqc-path", rcxc_o0_as_nqc(d)});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(r.out.find("DIFFERENT"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("[light levels and rotation] once"), std::string::npos) << r.out;
}

// --scenario before the file takes one value: the file is not read as a
// second scenario. The press at 200 ms lets both programs play.
TEST(CompareCli, ScenarioBeforeTheFile) {
  TempDir d;
  std::string scenario = d.write("press.toml", "[[input]]\nat_ms = 200\nsensor = 1\nraw = 100\n");
  auto r = run_rcxc({"compare", "--nqc-path", fake_nqc(d, image_playing(d, 3)), "--scenario", scenario,
                     d.write("p.nqc", kSource), "--for", "5000"});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("press.toml"), std::string::npos) << r.out;
}

// Two locals of one block, the first dead before the second is set: rcxc
// gives them one slot (named after the first), nqc two (both are in scope).
// The slot named `first` ends at 20 under rcxc and 10 under nqc, but no
// robot shows a local: compare judges the globals.
TEST(CompareCli, LocalsInDifferentSlotsAreNoDifference) {
  if (::access("/usr/bin/nqc", X_OK) != 0) GTEST_SKIP() << "nqc is not installed";
  TempDir d;
  auto src = d.write("p.nqc",
                     "int total;\n"
                     "task main() {\n"
                     "  int first;\n  first = Message() + 10;\n  total = first;\n"
                     "  int second;\n  second = Message() + 20;\n  total += second;\n"
                     "}\n");
  auto r = run_rcxc({"compare", src, "--scenario", d.write("idle.toml", "")});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  // An empty scenario is one of no inputs, which compare says.
  EXPECT_NE(r.err.find("idle.toml holds no [[input]] tables: its runs have no inputs"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("DIFFERENT"), std::string::npos) << r.out;
  // The global still counts: a program whose total differs is different.
  auto other = d.write("other.nqc", "int total;\ntask main() { total = 31; }\n");
  auto fake = d.write("fake-nqc", "#!/bin/sh\nfor a in \"$@\"; do case \"$a\" in -O*) o=\"${a#-O}\";; esac; done\n"
                                  "exec '" RCXC_BINARY "' compile -o \"$o\" '" + other + "'\n");
  chmod(fake.c_str(), 0755);
  r = run_rcxc({"compare", src, "--scenario", d.path + "/idle.toml", "--nqc-path", fake});
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("global 'total' = 30 (rcxc) but 31 (nqc)"), std::string::npos) << r.out;
}

// A loop that switches an output on every pass shows as many switches as
// its code goes round: -O2's loop (two instructions; the local is dead) runs
// twice as fast as -O0's, so the same switches come further and further
// apart. Nothing but time differs, and compare says so in one line instead
// of listing every switch.
TEST(CompareCli, RunsThatDifferInTimingOnlySaySoInOneLine) {
  TempDir d;
  std::string src = d.write("p.nqc", "task main() { int x; On(OUT_A); while (true) { x = 1; x += 2; Toggle(OUT_A); } }\n");
  auto r = run_rcxc({"compare", src, "--for", "2000", "--nqc-path", rcxc_o0_as_nqc(d)});
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("[idle] in timing only: the same "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("events in the same order, rcxc's code up to "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  first: output A on"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("; at a tenth of the instruction time the difference shrinks, as one of speed does\n"),
            std::string::npos) << r.out;
  EXPECT_EQ(r.out.find(" | "), std::string::npos) << "no side by side:\n" << r.out;
  EXPECT_LT(std::count(r.out.begin(), r.out.end(), '\n'), 20) << r.out;
}

// The same events in the same order, one a second sooner in one run because
// a task saw a value the other never showed (nqc's stand-in sets x to 2 for a
// moment before its wait): compare_runs calls that "timing only", but it is
// as far apart at a tenth of the instruction time, which a difference of
// speed is not. It used to be reported as timing only, as a buzzing loop is.
TEST(CompareCli, ASoonerEventCausedByAnotherValueIsNotTimingOnly) {
  TempDir d;
  const std::string watcher = "task watcher() { until (x == 2); PlaySound(SOUND_UP); }\n";
  std::string src = d.write("p.nqc", "int x;\n" + watcher +
                                         "task main() { start watcher; x = 1; Wait(100); x = 2; }\n");
  std::string other = d.write("other.nqc", "int x;\n" + watcher +
                                                "task main() { start watcher; x = 2; Wait(5); x = 1; Wait(100); x = 2; }\n");
  auto fake = d.write("fake-nqc", "#!/bin/sh\nfor a in \"$@\"; do case \"$a\" in -O*) o=\"${a#-O}\";; esac; done\n"
                                  "exec '" RCXC_BINARY "' compile -o \"$o\" '" + other + "'\n");
  chmod(fake.c_str(), 0755);
  auto r = run_rcxc({"compare", src, "--scenario", d.write("idle.toml", ""), "--nqc-path", fake});
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_EQ(r.out.find("in timing only"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("DIFFERENT " + src + " [" + d.path + "/idle.toml]: the same 1 events in the same order, but not "
                       "a difference of speed, which shrinks with the instruction time: sounds: the 1st event both "
                       "show (sound 3) is 1000.0 ms apart at 10 us an instruction and 1000.0 ms apart at 1 us an "
                       "instruction\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find(" | "), std::string::npos) << "a side by side:\n" << r.out;
}

// When the switches have drifted apart and then a press stops the output,
// one run stops it after another number of switches than the other, so its
// direction before the stop differs: more than time. The side by side shows the
// rows around the first event that differs but for its time, and says how
// many it left out; --all-rows shows them all.
TEST(CompareCli, ALongSideBySideShowsTheRowsAroundTheFirstDifference) {
  TempDir d;
  std::string src = d.write("p.nqc",
                            "task main() { int x; SetSensor(SENSOR_1, SENSOR_TOUCH); On(OUT_A);\n"
                            "  while (true) { x = 1; x += 2; if (SENSOR_1 == 1) Off(OUT_A); else { On(OUT_A); Toggle(OUT_A); } } }\n");
  auto r = run_rcxc({"compare", src, "--for", "2000", "--nqc-path", rcxc_o0_as_nqc(d)});
  EXPECT_EQ(r.exit_code, 1) << r.out;
  auto at = r.out.find("DIFFERENT " + src + " [touch and messages]\n");
  ASSERT_NE(at, std::string::npos) << r.out.substr(0, 4000);
  std::string touch = r.out.substr(at, r.out.find("DIFFERENT", at + 1) - at);
  EXPECT_NE(touch.find(" rows before\n"), std::string::npos) << touch;
  EXPECT_NE(touch.find(" rows after (--all-rows shows every row)\n"), std::string::npos) << touch;
  EXPECT_NE(touch.find("output A off"), std::string::npos) << "the first difference is in the window:\n" << touch;
  EXPECT_LT(std::count(touch.begin(), touch.end(), '\n'), 60) << touch;
  auto all = run_rcxc({"compare", src, "--for", "2000", "--all-rows", "--nqc-path", rcxc_o0_as_nqc(d)});
  EXPECT_GT(std::count(all.out.begin(), all.out.end(), '\n'), 1000);
  EXPECT_EQ(all.out.find(" rows before\n"), std::string::npos);
}
