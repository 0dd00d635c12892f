// rcxc's listing in nqc's layout (`rcxc nqc -L`) against nqc's own: nqc
// compiles each program to an image and lists it; rcxc lists that same
// image, and the two texts must be equal to the byte. Programs: a set that
// reaches every instruction nqc emits for the RCX (written here), and every
// corpus program nqc compiles. Skipped when nqc is absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "backend/nqc_listing.h"
#include "rcx/image.h"
#include "tests/support/process.h"

namespace rcxc {
namespace {

namespace fs = std::filesystem;

// nqc's listing of `file` and rcxc's listing of nqc's image of it; nullopt
// when nqc does not compile the file.
struct Listings {
  std::string nqc, rcxc;
};
std::optional<Listings> both(const std::string& nqc, const fs::path& file, const std::string& dir,
                             backend::ListingStyle style = backend::ListingStyle::Nqc) {
  std::string image_path = dir + "/image.rcx";
  fs::remove(image_path);
  auto compiled = test::run_process({nqc, "-Trcx", "-O" + image_path, file.string()});
  if (compiled.exit_code != 0) return std::nullopt;
  // nqc -c never ends on a byte it cannot name: such programs are left out.
  std::vector<std::string> list = {nqc, "-Trcx", "-L", file.string()};
  if (style == backend::ListingStyle::Lasm) list.insert(list.begin() + 2, "-c");
  auto listed = test::run_process(list, "", 10000);
  if (listed.exit_code != 0) return std::nullopt;
  auto image = rcx::read_image_file(image_path);
  if (auto* e = std::get_if<rcx::ImageError>(&image)) {
    ADD_FAILURE() << file << ": " << e->message;
    return std::nullopt;
  }
  return Listings{listed.out, backend::nqc_listing(std::get<rcx::Image>(image), {}, style)};
}

constexpr const char* kEveryInstruction = R"(
int x, y;
int far_counter;
sub helper() { x++; }
task other() { y = -3; }
task main() {
  int local;
  x = Timer(0); x = SENSOR_1; x = Random(5); x = Message(); x = SensorType(SENSOR_2); x = SensorMode(SENSOR_1);
  x = SensorValueRaw(SENSOR_1); x = SensorValueBool(SENSOR_1); x = Watch(); x = Program(); x = @(0x30001);
  SetSensor(SENSOR_1, SENSOR_TOUCH); SetSensor(SENSOR_2, SENSOR_LIGHT); SetSensor(SENSOR_3, SENSOR_ROTATION);
  SetSensorMode(SENSOR_1, SENSOR_MODE_RAW); SetSensorMode(SENSOR_1, SENSOR_MODE_EDGE);
  SetSensorMode(SENSOR_1, SENSOR_MODE_PULSE); SetSensorMode(SENSOR_1, SENSOR_MODE_CELSIUS);
  SetSensorMode(SENSOR_1, SENSOR_MODE_FAHRENHEIT); SetSensorType(SENSOR_1, SENSOR_TYPE_TEMPERATURE);
  SetSensorType(SENSOR_1, SENSOR_TYPE_NONE);
  OnFwd(OUT_A + OUT_C); OnRev(OUT_B); Off(OUT_C); Float(OUT_A); Toggle(OUT_B); SetPower(OUT_A, x);
  SetPower(OUT_B, Random(3)); SetPower(OUT_ABC, OUT_FULL);
  Wait(100); Wait(x); Wait(Random(20)); PlayTone(440, 50); PlaySound(SOUND_UP); ClearTimer(1);
  SendMessage(4); SendMessage(x); ClearMessage(); SelectDisplay(DISPLAY_SENSOR_1); SelectDisplay(x);
  CreateDatalog(10); AddToDatalog(x); AddToDatalog(Timer(2)); AddToDatalog(SENSOR_2); ClearSensor(SENSOR_1);
  repeat(3) { x++; } repeat(x) { y--; }
  start other; stop other; helper();
  x *= 3; x /= 2; x &= 4; x |= 1; x -= 2; x = abs(y); x = sign(y); x = -32768; local = x * y; y = local;
  SetWatch(1, 2); SetTxPower(TX_POWER_HI); SetSleepTime(5);
  if (x > 3 && SENSOR_1 == 1) x = 2; else y = 1;
  if (x <= y || x != 7) y = 4;
  while (x == 1) { x = y; }
  until (Timer(0) < 5);
  while (far_counter < 10) {
    far_counter++; PlayTone(100, 1); PlayTone(200, 1); PlayTone(300, 1); PlayTone(400, 1); PlayTone(500, 1);
    PlayTone(600, 1); PlayTone(700, 1); PlayTone(800, 1); PlayTone(900, 1); PlayTone(1000, 1); PlayTone(1100, 1);
    PlayTone(1200, 1); PlayTone(1300, 1); PlayTone(1400, 1); PlayTone(1500, 1); PlayTone(1600, 1);
    PlayTone(1700, 1); PlayTone(1800, 1); PlayTone(1900, 1); PlayTone(2000, 1); PlayTone(2100, 1);
    PlayTone(2200, 1); PlayTone(2300, 1); PlayTone(2400, 1); PlayTone(2500, 1); PlayTone(2600, 1);
    PlayTone(2700, 1); PlayTone(2800, 1); PlayTone(2900, 1); PlayTone(3000, 1); PlayTone(3100, 1);
    PlayTone(3200, 1); PlayTone(3300, 1); PlayTone(3400, 1);
  }
  StopAllTasks(); SleepNow();
}
)";

TEST(NqcListing, EveryInstructionListsAsNqcListsIt) {
  std::string nqc = test::find_nqc();
  if (nqc.empty()) GTEST_SKIP() << "nqc is not installed";
  test::TempDir dir;
  fs::path file = fs::path(dir.path) / "every.nqc";
  std::ofstream(file) << kEveryInstruction;
  auto l = both(nqc, file, dir.path);
  ASSERT_TRUE(l) << "nqc did not compile the program";
  // The program must reach what it claims: a far branch and a far loop.
  EXPECT_NE(l->nqc.find("chkl"), std::string::npos);
  EXPECT_NE(l->nqc.find("jmpl"), std::string::npos);
  EXPECT_EQ(l->rcxc, l->nqc);
}

TEST(NqcListing, CorpusProgramsListAsNqcListsThem) {
  std::string nqc = test::find_nqc();
  if (nqc.empty()) GTEST_SKIP() << "nqc is not installed";
  const fs::path corpus = RCXC_CORPUS_DIR;
  if (!fs::exists(corpus)) GTEST_SKIP() << "no corpus at " << corpus;
  test::TempDir dir;
  int compared = 0;
  for (const auto& e : fs::recursive_directory_iterator(corpus)) {
    if (e.path().extension() != ".nqc") continue;
    auto l = both(nqc, e.path(), dir.path);
    if (!l) continue;
    ++compared;
    EXPECT_EQ(l->rcxc, l->nqc) << e.path();
  }
  EXPECT_GT(compared, 10);
}

// nqc's -c: the listing LASM reads (operand fields as numbers, labels for
// branch targets in tasks and subroutines), equal to nqc's to the byte.
TEST(NqcListing, EveryInstructionListsForLasmAsNqcListsIt) {
  std::string nqc = test::find_nqc();
  if (nqc.empty()) GTEST_SKIP() << "nqc is not installed";
  test::TempDir dir;
  fs::path file = fs::path(dir.path) / "every.nqc";
  std::ofstream(file) << kEveryInstruction
                      << "int z;\nsub looping() { while (z < 3) z++; repeat (2) z--; }\ntask third() { looping(); }\n";
  auto l = both(nqc, file, dir.path, backend::ListingStyle::Lasm);
  ASSERT_TRUE(l) << "nqc did not compile the program";
  EXPECT_NE(l->nqc.find("\tchkl\t"), std::string::npos);
  EXPECT_NE(l->nqc.find("\tends\n"), std::string::npos);
  EXPECT_NE(l->nqc.find("\ns001"), std::string::npos);  // a label in sub 1
  EXPECT_EQ(l->rcxc, l->nqc);
}

TEST(NqcListing, CorpusAndSemanticTestProgramsListForLasmAsNqcListsThem) {
  std::string nqc = test::find_nqc();
  if (nqc.empty()) GTEST_SKIP() << "nqc is not installed";
  test::TempDir dir;
  int compared = 0;
  for (const fs::path& folder : {fs::path(RCXC_CORPUS_DIR), fs::path(RCXC_SOURCE_DIR) / "tests/semantic"}) {
    if (!fs::exists(folder)) continue;
    for (const auto& e : fs::recursive_directory_iterator(folder)) {
      if (e.path().extension() != ".nqc") continue;
      auto l = both(nqc, e.path(), dir.path, backend::ListingStyle::Lasm);
      if (!l) continue;
      ++compared;
      EXPECT_EQ(l->rcxc, l->nqc) << e.path();
    }
  }
  EXPECT_GT(compared, 100);
}

// An asm block can put a request in a program (the brick will not run it):
// nqc names each one it knows, in either toggle form, with its operands,
// and lists Transfer data and a request cut short a byte at a time (where
// nqc -c never ends, so its listing is compared without them).
constexpr const char* kRequestsInCode =
    "0xa4, 1, 0, 2, 0, 0x12, 0, 1, 0x12, 9, 1, 0x15, 1, 2, 3, 4, 5, 0x75, 1, 2, 3, 4, 5, 0x25, 7, 1, 0, 10, 0, "
    "0x10, 0x20, 0x30, 0x35, 7, 1, 0, 10, 0, 0xa5, 1, 2, 3, 4, 5, 0xac, 3, 0, 4, 0, 0x18, 0x1a, 0, 1";
constexpr const char* kUnnamedInCode = ", 0x45, 1, 0, 1, 0, 7, 7, 0xa4, 1";

TEST(NqcListing, RequestsInCodeListAsNqcListsThem) {
  std::string nqc = test::find_nqc();
  if (nqc.empty()) GTEST_SKIP() << "nqc is not installed";
  test::TempDir dir;
  fs::path file = fs::path(dir.path) / "requests.nqc";
  std::ofstream(file) << "task main() { asm { " << kRequestsInCode << kUnnamedInCode << " }; }\n";
  auto l = both(nqc, file, dir.path);
  ASSERT_TRUE(l) << "nqc did not compile the program";
  EXPECT_NE(l->nqc.find("polld    1, 2 "), std::string::npos) << l->nqc;
  EXPECT_EQ(l->rcxc, l->nqc);
  std::ofstream(file) << "task main() { asm { " << kRequestsInCode << " }; }\n";
  auto lasm = both(nqc, file, dir.path, backend::ListingStyle::Lasm);
  ASSERT_TRUE(lasm) << "nqc did not compile the program";
  EXPECT_NE(lasm->nqc.find("\tpolld\t1, 2 \n"), std::string::npos) << lasm->nqc;
  EXPECT_EQ(lasm->rcxc, lasm->nqc);
}

// Where nqc -c stops and never ends, rcxc writes a comment and goes on.
TEST(NqcListing, ABytePastTheInstructionsIsACommentForLasm) {
  rcx::Image image;
  image.fragments.push_back({rcx::FragmentType::Task, 0, {0x01, 0x51, 0x02}});
  image.symbols.push_back({rcx::SymbolType::Task, 0, "main"});
  EXPECT_EQ(backend::nqc_listing(image, {}, backend::ListingStyle::Lasm),
            "\n; Task 0 = main, size: 3 bytes\n;main\n\ttask\t0\n\t; 01: not an instruction\n\tplays\t2 \n\tendt\n"
            "\n;Total size: 3 bytes\n");
}

}  // namespace
}  // namespace rcxc
