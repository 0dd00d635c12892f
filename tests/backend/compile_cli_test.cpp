// `rcxc compile` end to end: the image it writes, -o, --listing, -O, -v,
// and the exit codes.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "rcx/image.h"
#include "tests/support/process.h"

using rcxc::test::run_rcxc;
using rcxc::test::TempDir;

namespace {


const char* kProgram = R"(int count;
task main() {
  count = 0;
  repeat (3) count++;
  PlaySound(SOUND_UP);
}
)";

}  // namespace

TEST(CompileCli, WritesAnImageNextToTheSource) {
  TempDir d;
  auto r = run_rcxc({"compile", d.write("p.nqc", kProgram)});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto bytes = d.read("p.rcx");
  auto image = rcx::read_image(bytes);
  ASSERT_TRUE(std::holds_alternative<rcx::Image>(image));
  const auto& img = std::get<rcx::Image>(image);
  ASSERT_NE(img.find(rcx::FragmentType::Task, 0), nullptr);
  EXPECT_EQ(img.name_of(rcx::SymbolType::Task, 0), "main");
  EXPECT_EQ(img.name_of(rcx::SymbolType::Variable, 0), "count");
}

TEST(CompileCli, OutputOptionAndListingToStdout) {
  TempDir d;
  auto r = run_rcxc({"compile", d.write("p.nqc", kProgram), "-o", d.path + "/out.rcx", "--listing"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(d.read("out.rcx").empty());
  EXPECT_NE(r.out.find("task 0 main"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("loopset"), std::string::npos) << r.out;  // repeat uses the loop counter
  EXPECT_NE(r.out.find("p.nqc:4:"), std::string::npos) << r.out;  // source lines
}

TEST(CompileCli, ATestIsListedUnderTheLineOfItsStatement) {
  // The chk of the `if` ends the task's first block, which the task's own
  // line opened: it was listed under `task main() {`.
  TempDir d;
  const char* program = "int a, b;\ntask main() {\n  a = 1;\n  if (a > 2) b = 1;\n  b = 2;\n}\n";
  auto r = run_rcxc({"compile", "-O0", d.write("p.nqc", program), "-o", d.path + "/p.rcx", "--listing"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto at_if = r.out.find("p.nqc:4:");
  auto chk = r.out.find("chk");
  ASSERT_NE(at_if, std::string::npos) << r.out;
  ASSERT_NE(chk, std::string::npos) << r.out;
  EXPECT_LT(at_if, chk) << r.out;
  EXPECT_EQ(r.out.find("p.nqc:2:", r.out.find("p.nqc:3:")), std::string::npos) << r.out;
}

TEST(CompileCli, ListingToAFile) {
  TempDir d;
  auto r = run_rcxc({"compile", d.write("p.nqc", kProgram), "--listing=" + d.path + "/p.lst"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto text = d.read("p.lst");
  EXPECT_NE(std::string(text.begin(), text.end()).find("sound"), std::string::npos);
}

TEST(CompileCli, VerboseReportsDecisions) {
  TempDir d;
  auto r = run_rcxc({"compile", d.write("p.nqc", "sub a() { PlaySound(1); }\nsub b() { a(); }\ntask main() { b(); b(); }\n"),
                     "-v", "-O1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("sub a inlined into sub b"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bytes of code"), std::string::npos) << r.err;
}

TEST(CompileCli, OneSlotIsASlotNotSlots) {
  TempDir d;
  std::string one = d.write("one.nqc", "int x;\ntask main() { x = Message(); SendMessage(x); }\n");
  std::string none = d.write("none.nqc", "task main() { PlaySound(1); }\n");
  auto r1 = run_rcxc({"compile", one, "-v", "--listing", "-o", d.path + "/one.rcx"});
  auto r0 = run_rcxc({"compile", none, "-v", "--listing", "-o", d.path + "/none.rcx"});
  ASSERT_EQ(r1.exit_code, 0) << r1.err;
  ASSERT_EQ(r0.exit_code, 0) << r0.err;
  EXPECT_NE(r1.err.find("bytes of code, 1 variable slot\n"), std::string::npos) << r1.err;
  EXPECT_NE(r1.out.find("bytes of code, 1 variable slot\n"), std::string::npos) << r1.out;
  EXPECT_NE(r0.err.find("bytes of code, 0 variable slots\n"), std::string::npos) << r0.err;
  EXPECT_NE(r0.out.find("bytes of code, 0 variable slots\n"), std::string::npos) << r0.out;
}

TEST(CompileCli, OptimisationLevelsDiffer) {
  TempDir d;
  std::string src = d.write("p.nqc", "int x;\ntask main() { OnFwd(OUT_A); Wait(10); OnFwd(OUT_A); x = 2 + 3; }\n");
  auto o0 = run_rcxc({"compile", src, "-O0", "-o", d.path + "/o0.rcx"});
  auto os = run_rcxc({"compile", src, "-Os", "-o", d.path + "/os.rcx"});
  ASSERT_EQ(o0.exit_code, 0) << o0.err;
  ASSERT_EQ(os.exit_code, 0) << os.err;
  EXPECT_LT(d.read("os.rcx").size(), d.read("o0.rcx").size());
}

// The default is -O2, the fastest code: a loop body written twice stays in
// the loop, where -Os would move it into a subroutine (a call and a return
// per pass) for fewer bytes.
TEST(CompileCli, TheDefaultLevelIsMinusO2) {
  TempDir d;
  std::string src = d.write("p.nqc", R"(int x;
task main() {
  while (true) {
    OnFwd(OUT_A); Wait(20); x += 3; PlaySound(1); Off(OUT_A); Wait(20);
    OnFwd(OUT_A); Wait(20); x += 3; PlaySound(1); Off(OUT_A); Wait(20);
  }
}
)");
  auto plain = run_rcxc({"compile", src, "-o", d.path + "/default.rcx"});
  auto o2 = run_rcxc({"compile", src, "-O2", "-o", d.path + "/o2.rcx", "-v"});
  auto os = run_rcxc({"compile", src, "-Os", "-o", d.path + "/os.rcx", "-v"});
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(o2.exit_code, 0) << o2.err;
  ASSERT_EQ(os.exit_code, 0) << os.err;
  EXPECT_EQ(d.read("default.rcx"), d.read("o2.rcx"));
  EXPECT_NE(d.read("os.rcx"), d.read("o2.rcx"));
  EXPECT_NE(os.err.find("outlined into sub"), std::string::npos) << os.err;
  EXPECT_EQ(o2.err.find("outlined"), std::string::npos) << o2.err;
  auto help = run_rcxc({"compile", "--help"});
  EXPECT_NE(help.out.find("-O2 (default)"), std::string::npos) << help.out;
}

TEST(CompileCli, ErrorsExitWithOne) {
  TempDir d;
  auto r = run_rcxc({"compile", d.write("p.nqc", "task main() { x = 1; }\n")});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("error"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(d.path + "/p.rcx"));
}

TEST(CompileCli, BadOptimisationLevelIsUsageError) {
  TempDir d;
  auto r = run_rcxc({"compile", d.write("p.nqc", kProgram), "-O3"});
  EXPECT_EQ(r.exit_code, 2);
}

TEST(CompileCli, AProblemInsideALibraryCallIsReportedAtTheCall) {
  // 316 does not fit sensmode's byte: the warning belongs to line 3 of the
  // user's file, with a note showing the library line it came from.
  TempDir d;
  auto r = run_rcxc({"compile", d.write("p.nqc", "task main()\n{\n  SetSensorMode(SENSOR_1, 316);\n}\n"), "-o",
                     d.path + "/p.rcx"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.rfind(d.path + "/p.nqc:3:3: warning:", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("rcx.nqh:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("note: in inline function 'SetSensorMode'"), std::string::npos) << r.err;
}

TEST(CompileCli, AProblemInNestedInlineFunctionsNamesEveryCall) {
  // The value only goes wrong once outer(16) passes 316 down: reported at
  // that call, then each call on the way to the library line.
  TempDir d;
  const char* src =
      "void inner(const int m) { SetSensorMode(SENSOR_1, m); }\n"
      "void outer(const int k) { inner(k + 300); }\n"
      "task main()\n{\n  outer(16);\n}\n";
  auto r = run_rcxc({"compile", d.write("p.nqc", src), "-o", d.path + "/p.rcx"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.rfind(d.path + "/p.nqc:5:3: warning:", 0), 0u) << r.err;
  auto outer = r.err.find("p.nqc:2:27: note: in inline function 'outer', which calls it here");
  auto inner = r.err.find("p.nqc:1:27: note: in inline function 'inner', which calls it here");
  auto library = r.err.find("note: in inline function 'SetSensorMode'");
  ASSERT_NE(outer, std::string::npos) << r.err;
  ASSERT_NE(inner, std::string::npos) << r.err;
  ASSERT_NE(library, std::string::npos) << r.err;
  EXPECT_LT(outer, inner);
  EXPECT_LT(inner, library);
}

TEST(CompileCli, NeverWritesOverTheSource) {
  TempDir d;
  std::string src = d.write("p.nqc", kProgram);
  auto r = run_rcxc({"compile", src, "-o", src});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("refusing to write"), std::string::npos) << r.err;
  auto listing = run_rcxc({"compile", src, "--listing=" + src});
  EXPECT_EQ(listing.exit_code, 2);
  auto kept = d.read("p.nqc");
  EXPECT_EQ(std::string(kept.begin(), kept.end()), kProgram);
}

TEST(CompileCli, NeverWritesOverAnIncludedFile) {
  TempDir d;
  d.write("lib.nqh", "#define N 3\n");
  std::string src = d.write("p.nqc", "#include \"lib.nqh\"\ntask main() { Wait(N); }\n");
  auto r = run_rcxc({"compile", src, "-o", d.path + "/lib.nqh"});
  EXPECT_EQ(r.exit_code, 2);
  auto kept = d.read("lib.nqh");
  EXPECT_EQ(std::string(kept.begin(), kept.end()), "#define N 3\n");
}

TEST(CompileCli, ABrokenProgramLeavesThePreviousImage) {
  TempDir d;
  std::string src = d.write("p.nqc", kProgram);
  ASSERT_EQ(run_rcxc({"compile", src}).exit_code, 0);
  auto before = d.read("p.rcx");
  // A broken program writes nothing; the old image stays as it was.
  d.write("p.nqc", "task main() { x = ; }\n");
  EXPECT_EQ(run_rcxc({"compile", src}).exit_code, 1);
  EXPECT_EQ(d.read("p.rcx"), before);
  // No temporary is left behind either.
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(d.path)) ++files;
  EXPECT_EQ(files, 2u);
}

TEST(CompileCli, AnImageGivenAsSourceIsOneClearError) {
  TempDir d;
  std::string src = d.write("p.nqc", kProgram);
  ASSERT_EQ(run_rcxc({"compile", src, "-o", d.path + "/p.rcx"}).exit_code, 0);
  auto r = run_rcxc({"compile", d.path + "/p.rcx", "-o", d.path + "/q.rcx"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("is an RCX image, not NQC source"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  std::vector<std::uint8_t> binary = {'t', 'a', 's', 'k', 0, 1, 2};
  d.write("b.nqc", binary);
  auto b = run_rcxc({"compile", d.path + "/b.nqc", "-o", d.path + "/b.rcx"});
  EXPECT_EQ(b.exit_code, 1);
  EXPECT_NE(b.err.find("binary data"), std::string::npos) << b.err;
}

TEST(CompileCli, BadMacroNamesAndAnEmptyOutputAreUsageErrors) {
  TempDir d;
  std::string src = d.write("p.nqc", kProgram);
  for (std::vector<std::string> extra : {std::vector<std::string>{"-D=3"}, {"-D3X=1"}, {"-U="}, {"-o", ""}}) {
    std::vector<std::string> args{"compile", src};
    args.insert(args.end(), extra.begin(), extra.end());
    auto r = run_rcxc(args);
    EXPECT_EQ(r.exit_code, 2) << extra[0] << ": " << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(d.path + "/p.rcx"));
  EXPECT_EQ(run_rcxc({"compile", src, "-DGOOD_NAME=2", "-UOTHER"}).exit_code, 0);
}

// Options before the file, as nqc and IDEs write them: each -I/-D/-U/-W
// takes one value, so the file is not swallowed as a second define.
TEST(CompileCli, RepeatableOptionsBeforeTheFile) {
  TempDir d;
  std::filesystem::create_directories(d.path + "/inc");
  d.write("inc/count.nqh", "#define COUNT_TO TIMES\n");
  std::string src = d.write("p.nqc", "#include \"count.nqh\"\nint count;\ntask main() { repeat (COUNT_TO) count++; }\n");
  auto r = run_rcxc({"compile", "-I", d.path + "/inc", "-DTIMES=4", "-D", "UNUSED", "-UOTHER", "-Werror", src, "-o",
                     d.path + "/p.rcx"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto image = rcx::read_image(d.read("p.rcx"));
  ASSERT_TRUE(std::holds_alternative<rcx::Image>(image));
  // Without the define the program does not compile: the option reached it.
  EXPECT_EQ(run_rcxc({"compile", "-I", d.path + "/inc", src, "-o", d.path + "/q.rcx"}).exit_code, 1);
}

// "-" as the program: the standard input, as nqc takes it, for editors and
// scripts that pipe a buffer through; `-o -` writes the image to the
// standard output.
TEST(CompileCli, TheStandardInputIsAProgramAndTheStandardOutputTakesTheImage) {
  TempDir d;
  ASSERT_EQ(run_rcxc({"compile", d.write("p.nqc", kProgram), "-o", d.path + "/file.rcx"}).exit_code, 0);
  auto from_file = d.read("file.rcx");
  ASSERT_FALSE(from_file.empty());

  auto piped = run_rcxc({"compile", "-", "-o", d.path + "/piped.rcx"}, kProgram);
  ASSERT_EQ(piped.exit_code, 0) << piped.err;
  EXPECT_EQ(d.read("piped.rcx"), from_file);

  auto to_stdout = run_rcxc({"compile", "-", "-o", "-"}, kProgram);
  ASSERT_EQ(to_stdout.exit_code, 0) << to_stdout.err;
  EXPECT_EQ(std::vector<std::uint8_t>(to_stdout.out.begin(), to_stdout.out.end()), from_file);
  EXPECT_FALSE(std::filesystem::exists("-"));

  auto broken = run_rcxc({"compile", "-", "-o", d.path + "/broken.rcx"}, "task main() { Wait(1) }\n");
  EXPECT_EQ(broken.exit_code, 1);
  EXPECT_NE(broken.err.find("<stdin>:1:22: error: expected ';'"), std::string::npos) << broken.err;

  auto preprocessed = run_rcxc({"compile", "-E", "-", "-n"}, "#define N 3\nint x = N;\n");
  EXPECT_EQ(preprocessed.exit_code, 0) << preprocessed.err;
  EXPECT_NE(preprocessed.out.find("int x = 3;"), std::string::npos) << preprocessed.out;
}

TEST(CompileCli, TheStandardInputFindsIncludesInTheCurrentFolder) {
  TempDir d;
  d.write("count.nqh", "#define COUNT_TO 4\n");
  auto r = rcxc::test::run_process(
      {"/bin/sh", "-c", "cd '" + d.path + "' && '" RCXC_BINARY "' compile - -o p.rcx"},
      "#include \"count.nqh\"\nint count;\ntask main() { repeat (COUNT_TO) count++; }\n");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::holds_alternative<rcx::Image>(rcx::read_image(d.read("p.rcx"))));
}

TEST(CompileCli, WhereTheStandardStreamsCannotServeItIsAUsageError) {
  // No name to make FILE.rcx of; an image and a listing both on stdout.
  auto unnamed = run_rcxc({"compile", "-"}, kProgram);
  EXPECT_EQ(unnamed.exit_code, 2);
  EXPECT_NE(unnamed.err.find("name the image with -o FILE (-o - writes it to the standard output)"),
            std::string::npos)
      << unnamed.err;
  TempDir d;
  auto both = run_rcxc({"compile", d.write("p.nqc", kProgram), "-o", "-", "--listing"});
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_NE(both.err.find("would both go to the standard output"), std::string::npos) << both.err;
  EXPECT_TRUE(both.out.empty());
}
