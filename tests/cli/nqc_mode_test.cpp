// rcxc's nqc mode (`rcxc nqc ...`, or rcxc started as `nqc`) against the
// real nqc: the same command lines, in twin folders holding the same files,
// must give the same exit codes, create the same files and point at the same
// source lines (BricxCC jumps to the `line N` of each error).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "rcx/image.h"
#include "tests/support/process.h"

namespace {

using rcxc::test::run_process;
using rcxc::test::run_rcxc;
using rcxc::test::TempDir;
namespace fs = std::filesystem;

// An image of task main (pwr ABC, 7), for nqc's reading of FILE.rcx.
std::string image_bytes() {
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0, {0x13, 0x07, 0x02, 0x07}});
  img.symbols.push_back({rcx::SymbolType::Task, 0, "main"});
  auto bytes = rcx::write_image(img);
  return std::string(bytes.begin(), bytes.end());
}

const std::map<std::string, std::string> kFiles = {
    {"img.rcx", image_bytes()},
    {"text.RCX", "task main()\n{\n}\n"},  // named as an image, holding source
    {"ok.nqc", "task main()\n{\n  OnFwd(OUT_A);\n  Wait(100);\n}\n"},
    {"undeclared.nqc", "task main()\n{\n  OnFwd(OUT_A);\n  x = 1;\n}\n"},
    // Lines ended by a lone CR, as classic Mac OS editors wrote them.
    {"mac.nqc", "#define POWER 3\rtask main()\r{\r  SetPower(OUT_A, POWER);\r  OnFwd(OUT_A);\r}\r"},
    {"mac_error.nqc", "task main()\r{\r  OnFwd(OUT_A);\r  x = 1;\r}\r"},
    {"nocall.nqc", "task main()\n{\n  Wait(10);\n\n  Launch(3);\n}\n"},
    {"inc.nqc", "#include \"lib.nqh\"\ntask main()\n{\n  Go();\n}\n"},
    {"badinc.nqc", "#include \"badlib.nqh\"\ntask main()\n{\n  Go();\n}\n"},
    {"inc/lib.nqh", "void Go()\n{\n  OnFwd(OUT_A);\n}\n"},
    {"inc/badlib.nqh", "void Go()\n{\n  OnFwd(OUT_A);\n  Stopp(OUT_A);\n}\n"},
    {"defs.nqc", "int y;\ntask main()\n{\n#ifdef X\n  x = 1;\n#endif\n#if LEVEL != 2\n  z = 2;\n#endif\n  y = 1;\n}\n"},
    {"if_defined.nqc", "int y;\ntask main()\n{\n#if X\n  y = 2;\n#endif\n  y = 1;\n}\n"},
    {"plain.nqc", "int x;\ntask main()\n{\n  x = OUT_A;\n}\n"},
    // A missing ';': nqc points at the token after the gap, on the next
    // line here, past a comment and a blank line in semi_comment.nqc.
    {"semi.nqc", "task main()\n{\n  OnFwd(OUT_A)\n  Wait(100);\n}\n"},
    {"semi_decl.nqc", "task main()\n{\n  int x\n  x = 2;\n}\n"},
    {"semi_comment.nqc", "task main()\n{\n  Wait(1)  // one tick\n\n  /* then\n     stop */ Off(OUT_A);\n}\n"},
    // At the end of the file: the line after the last line end, if any.
    {"semi_eof.nqc", "task main()\n{\n}\nint a\n"},
    {"semi_eof_unended.nqc", "task main()\n{\n}\nint a"},
    // An included file is named as the #include spells it, folder and all.
    {"subinc.nqc", "#include \"sub/part.nqh\"\ntask main()\n{\n  Go();\n}\n"},
    {"sub/part.nqh", "void Go()\n{\n  OnFwd(OUT_A);\n  Stopp(OUT_A);\n}\n"},
    {"semi_inc.nqc", "#include \"sub/semi.nqh\"\ntask main()\n{\n  Go();\n}\n"},
    {"sub/semi.nqh", "void Go()\n{\n  OnFwd(OUT_A)\n}\n"},
};

struct Outcome {
  int exit_code = -1;
  std::string out;
  std::string err;
  std::set<std::string> created;  // files that were not there before
  std::string logs;               // the text of every created .log file
};

std::string shell_word(const std::string& s) { return "'" + s + "'"; }

// Runs `program ARGS` in a fresh folder holding kFiles.
Outcome run_in_folder(const std::string& program, const std::vector<std::string>& args, const std::string& env = "",
                      const std::string& stdin_text = "") {
  TempDir d;
  for (const auto& [name, text] : kFiles) {
    fs::create_directories(fs::path(d.path + "/" + name).parent_path());
    d.write(name, text);
  }
  std::string command = "cd " + shell_word(d.path) + " && exec env " + env + " " + shell_word(program);
  for (const auto& a : args) command += " " + shell_word(a);
  auto r = run_process({"/bin/sh", "-c", command}, stdin_text, 60000);
  Outcome o{r.exit_code, r.out, r.err, {}, {}};
  for (const auto& entry : fs::recursive_directory_iterator(d.path)) {
    std::string rel = fs::relative(entry.path(), d.path).string();
    if (entry.is_regular_file() && !kFiles.count(rel)) {
      o.created.insert(rel);
      if (entry.path().extension() == ".log") {
        std::ifstream in(entry.path());
        std::stringstream s;
        s << in.rdbuf();
        o.logs += s.str();
      }
    }
  }
  return o;
}

// The places the errors point at, as BricxCC reads them: file and line.
std::set<std::string> error_lines(const std::string& text) {
  std::set<std::string> lines;
  static const std::regex place("File \"([^\"]*)\" ; line ([0-9]+)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), place); it != std::sregex_iterator(); ++it)
    lines.insert((*it)[1].str() + ":" + (*it)[2].str());
  return lines;
}

bool have_nqc() { return ::access("/usr/bin/nqc", X_OK) == 0; }

// rcxc under the name nqc, through a symbolic link as an installation makes.
struct NqcLink {
  TempDir dir;
  std::string path = dir.path + "/nqc";
  NqcLink() { fs::create_symlink(RCXC_BINARY, path); }
};

struct Case {
  std::vector<std::string> args;
  std::string env;
  std::string stdin_text;
  Case(std::vector<std::string> a, std::string e = "", std::string in = "")
      : args(std::move(a)), env(std::move(e)), stdin_text(std::move(in)) {}
};

void expect_same_as_nqc(const Case& c) {
  NqcLink rcxc_as_nqc;
  Outcome theirs = run_in_folder("/usr/bin/nqc", c.args, c.env, c.stdin_text);
  Outcome ours = run_in_folder(rcxc_as_nqc.path, c.args, c.env, c.stdin_text);
  std::string call;
  for (const auto& a : c.args) call += " " + a;
  SCOPED_TRACE(c.env + " nqc" + call + "\n--- nqc:\n" + theirs.out + theirs.err + theirs.logs + "--- rcxc:\n" + ours.out +
               ours.err + ours.logs);
  EXPECT_EQ(ours.exit_code, theirs.exit_code);
  EXPECT_EQ(ours.created, theirs.created);
  EXPECT_EQ(ours.out.empty(), theirs.out.empty());
  EXPECT_EQ(error_lines(ours.err), error_lines(theirs.err));
  EXPECT_EQ(error_lines(ours.out), error_lines(theirs.out));
  EXPECT_EQ(error_lines(ours.logs), error_lines(theirs.logs));
}

TEST(NqcMode, CompilingBehavesAsNqc) {
  if (!have_nqc()) GTEST_SKIP() << "nqc is not installed";
  for (const Case& c : std::vector<Case>{
           {{"-Trcx", "ok.nqc"}},
           {{"-TRCX", "-Oout.rcx", "ok.nqc"}},
           {{"-L", "ok.nqc"}},
           {{"-Lx.lst", "ok.nqc"}},
           {{"-c", "-Llasm.lst", "ok.nqc"}},
           {{"-s", "-Lx.lst", "-Oy.rcx", "ok.nqc"}},
           {{"undeclared.nqc"}},
           {{"nocall.nqc"}},
           {{"-E", "undeclared.nqc"}},
           {{"-Eerr.log", "undeclared.nqc"}},
           {{"-Eerr.log", "ok.nqc"}},
           {{"-Omac.rcx", "mac.nqc"}},
           {{"mac_error.nqc"}},
           {{"missing.nqc"}},
           {{"-n", "plain.nqc"}},
           {{"plain.nqc"}},
           {{"defs.nqc"}},
           {{"-b", "ok.nqc"}},
           // nqc reads FILE.rcx (any case) as an image, -b or not, and lists it.
           {{"img.rcx"}},
           {{"-L", "img.rcx"}},
           {{"-b", "-Limg.lst", "img.rcx"}},
           {{"text.RCX"}},
           {{"-"}, "", kFiles.at("undeclared.nqc")},
           {{"-"}, "", kFiles.at("ok.nqc")},
           {{"-DLEVEL=2", "defs.nqc"}},
           {{"-DLEVEL=2", "-DX", "defs.nqc"}},
           {{"-DLEVEL=2", "-DX", "-UX", "defs.nqc"}},
           {{"-DX", "if_defined.nqc"}},  // nqc's -DX is empty, so `#if X` has no value
           // nqc takes a keyword as a -D name and never expands it.
           {{"-Dtask=1", "-Oout.rcx", "ok.nqc"}},
           {{"-Dint", "-Dacquire=2", "-Utask", "ok.nqc"}},
           {{"-Iinc", "inc.nqc"}},
           {{"inc.nqc"}, "NQC_INCLUDE=inc"},
           {{"ok.nqc"}, "NQC_OPTIONS=-Lq.lst"},
           {{"-api"}},
           {{"semi.nqc"}},
           {{"semi_decl.nqc"}},
           {{"semi_comment.nqc"}},
           {{"semi_eof.nqc"}},
           {{"semi_eof_unended.nqc"}},
           {{"subinc.nqc"}},
           {{"-Esemi.log", "semi_inc.nqc"}},
       })
    expect_same_as_nqc(c);
}

// BricxCC's own compile line, with a program that compiles, one with an
// error, and one whose error is in an included file.
TEST(NqcMode, BricxccCompileLineBehavesAsNqc) {
  if (!have_nqc()) GTEST_SKIP() << "nqc is not installed";
  for (const char* file : {"ok.nqc", "undeclared.nqc", "badinc.nqc"})
    expect_same_as_nqc({{"-Etemp.log", "-Ltemp.lst", "-Iinc", "-Iother", "-Trcx", "-Of.rcx", file}});
}

TEST(NqcMode, BadCommandLinesBehaveAsNqc) {
  if (!have_nqc()) GTEST_SKIP() << "nqc is not installed";
  for (const Case& c : std::vector<Case>{
           {std::vector<std::string>{}},
           {{"-Z", "ok.nqc"}},
           {{"-q", "-v"}},
           {{"-pgm"}},
           {{"ok.nqc", "-Lx.lst"}},  // an option after the file: the file is still compiled
           {{"ok.nqc", "undeclared.nqc"}},
           {{"-help"}},
           {{"-S/dev/no-such-tower", "-run"}},
           {{"-S/dev/no-such-tower", "-d", "ok.nqc"}},
           {{"-S/dev/no-such-tower", "-d", "undeclared.nqc"}},
           {{"-firmware", "no-such.srec"}},
           // An error file that cannot be written stops the call before it
           // compiles (rcxc compiled, wrote the image and lost the errors).
           {{"-Eno-such-folder/err.log", "-Oout.rcx", "ok.nqc"}},
           {{"-Eno-such-folder/err.log", "-Oout.rcx", "undeclared.nqc"}},
       })
    expect_same_as_nqc(c);
}

// From here on rcxc alone: the exact format BricxCC and users see.
TEST(NqcMode, ErrorsComeInNqcsFormat) {
  NqcLink nqc;
  auto o = run_in_folder(nqc.path, {"-Etemp.log", "-Trcx", "-Of.rcx", "undeclared.nqc"});
  EXPECT_EQ(o.exit_code, 243);
  EXPECT_EQ(o.logs,
            "# Error: 'x' is not declared\n"
            "File \"undeclared.nqc\" ; line 4\n"
            "#   x = 1;\n"
            "#   ^\n"
            "#----------------------------------------------------------\n"
            "# 1 error during compilation\n");
  EXPECT_EQ(o.created, (std::set<std::string>{"temp.log"}));
}

// A missing ';' is shown where nqc shows it, at the token found instead
// (which the message names), not at the end of the line before.
TEST(NqcMode, AMissingSemicolonIsAtTheTokenFound) {
  NqcLink nqc;
  auto o = run_in_folder(nqc.path, {"-Etemp.log", "semi.nqc"});
  EXPECT_EQ(o.exit_code, 243);
  EXPECT_EQ(o.logs,
            "# Error: expected ';' before 'Wait'\n"
            "File \"semi.nqc\" ; line 4\n"
            "#   Wait(100);\n"
            "#   ^^^^\n"
            "#----------------------------------------------------------\n"
            "# 1 error during compilation\n");
}

TEST(NqcMode, SubcommandIsTheSameMode) {
  TempDir d;
  std::string src = d.write("p.nqc", kFiles.at("undeclared.nqc"));
  auto r = run_rcxc({"nqc", "-Trcx", src});
  EXPECT_EQ(r.exit_code, 243);
  EXPECT_NE(r.err.find("File \"" + src + "\" ; line 4\n"), std::string::npos) << r.err;
}

// nqc has no levels; this mode compiles at rcxc compile's default (-O2, never
// slower than nqc's code). It compiled at -Os, the default when it was
// written, so BricxCC's programs polled a bumper more slowly than
// `rcxc compile` made them.
TEST(NqcMode, CompilesAtRcxcCompilesDefaultLevel) {
  TempDir d;
  std::string src = d.write("bump.nqc",
                            "int bumps;\ntask main()\n{\n  SetSensor(SENSOR_1, SENSOR_TOUCH);\n  while (true)\n  {\n"
                            "    if (SENSOR_1 == 1)\n    {\n      bumps++;\n      OnRev(OUT_A);\n      Wait(50);\n"
                            "      Rev(OUT_A);\n      Wait(40);\n      OnFwd(OUT_A);\n    }\n  }\n}\n");
  ASSERT_EQ(run_rcxc({"compile", src, "-o", d.path + "/native.rcx"}).exit_code, 0);
  ASSERT_EQ(run_rcxc({"compile", "-Os", src, "-o", d.path + "/small.rcx"}).exit_code, 0);
  auto r = run_rcxc({"nqc", "-Trcx", "-O" + d.path + "/nqc.rcx", src});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string native = rcxc::test::read_text_file(d.path + "/native.rcx");
  ASSERT_NE(native, rcxc::test::read_text_file(d.path + "/small.rcx"))
      << "the program no longer tells the levels apart";
  EXPECT_EQ(rcxc::test::read_text_file(d.path + "/nqc.rcx"), native);
}

// -L is nqc's layout (tests/backend/nqc_listing_test compares it with nqc's
// own on nqc's images); -s puts each source line above the first
// instruction made from it, as nqc does.
TEST(NqcMode, ListingWithSourceLinesIsNqcsLayout) {
  TempDir d;
  std::string src = d.write("s.nqc", "int x;\ntask main()\n{\n  x = 3;\n  PlaySound(2);\n}\n");
  auto r = run_rcxc({"nqc", "-L", "-s", src});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("*** Var 0 = x\n\n*** Task 0 = main, size: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  x = 3;\n006 setv     var[0], 3                         14 00 02 03 00 \n"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("  PlaySound(2);\n011 plays    2 "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\nTotal size: 13 bytes\n"), std::string::npos) << r.out;
}

TEST(NqcMode, AMacroErrorIsShownAtTheUsersLine) {
  TempDir d;
  std::string src = d.write("m.nqc", "#define BUMP y = y + 1\ntask main()\n{\n  BUMP;\n}\n");
  auto r = run_rcxc({"nqc", src});
  EXPECT_EQ(r.exit_code, 243);
  EXPECT_NE(r.err.find("; line 4\n#   BUMP;\n"), std::string::npos) << r.err;
}

TEST(NqcMode, OtherTargetsAreRefused) {
  for (const char* target : {"-TRCX2", "-TScout", "-TCM", "-TSpy", "-TSwan"}) {
    auto r = run_rcxc({"nqc", target, "ok.nqc"});
    EXPECT_EQ(r.exit_code, 244) << target;
    EXPECT_NE(r.err.find("not supported"), std::string::npos) << r.err;
  }
}

TEST(NqcMode, ApiPrintsTheStandardLibrary) {
  std::ifstream in(std::string(RCXC_SOURCE_DIR) + "/stdlib/rcx.nqh", std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  auto r = run_rcxc({"nqc", "-api"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out, s.str());
}

// The native command line rejects nqc's habits and says what to write.
TEST(NqcMode, NqcHabitsOnTheNativeCommandLineGetAHint) {
  TempDir d;
  std::string ok = d.write("ok.nqc", kFiles.at("ok.nqc"));
  auto e = run_rcxc({"compile", "-Etemp.log", ok});
  EXPECT_EQ(e.exit_code, 2);
  EXPECT_NE(e.err.find("'-Etemp.log' is nqc's option: errors always go to stderr here"), std::string::npos) << e.err;
  auto t = run_rcxc({"compile", "-Trcx", ok});
  EXPECT_EQ(t.exit_code, 2);
  EXPECT_NE(t.err.find("rcxc always compiles for the RCX"), std::string::npos) << t.err;
  auto l = run_rcxc({"compile", "-Lx.lst", ok});
  EXPECT_EQ(l.exit_code, 2);
  EXPECT_NE(l.err.find("write --listing=x.lst"), std::string::npos) << l.err;
  auto fine = run_rcxc({"compile", "--bogus", ok});
  EXPECT_EQ(fine.err.find("nqc's option"), std::string::npos) << fine.err;
}

// The hint is said alone: CLI11's "argument was not expected: -temp.log"
// named a word nobody typed (what it left of -Etemp.log once -E was taken).
TEST(NqcMode, ANqcHabitIsSaidOnceByItsHint) {
  TempDir d;
  std::string ok = d.write("ok.nqc", kFiles.at("ok.nqc"));
  for (std::vector<std::string> args : std::vector<std::vector<std::string>>{
           {"compile", "-Etemp.log", ok}, {"compile", "-Enames.log", ok}, {"compile", "-Trcx", ok},
           {"compile", "-Lx.lst", ok}, {"compile", ok, "-TRCX2", "-Lx.lst"}}) {
    auto r = run_rcxc(args);
    EXPECT_EQ(r.exit_code, 2) << args[1];
    EXPECT_NE(r.err.find("is nqc's option"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("not expected"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.rfind("rcxc: '-", 0), 0u) << r.err;  // the hint comes first
  }
  // Two habits, two hints: the second is not left unsaid.
  auto two = run_rcxc({"compile", ok, "-TRCX2", "-Lx.lst"});
  EXPECT_NE(two.err.find("'-TRCX2' is nqc's option"), std::string::npos) << two.err;
  EXPECT_NE(two.err.find("'-Lx.lst' is nqc's option"), std::string::npos) << two.err;
  // A word no habit explains is still said beside the hint.
  auto other = run_rcxc({"compile", "-Etemp.log", ok, "extra.nqc"});
  EXPECT_EQ(other.exit_code, 2);
  EXPECT_NE(other.err.find("extra.nqc"), std::string::npos) << other.err;
  EXPECT_NE(other.err.find("is nqc's option"), std::string::npos) << other.err;
}

TEST(NqcMode, ActionsAfterAFailureDoNotRun) {
  NqcLink nqc;
  // The compile error stops the call before -api would print anything.
  auto o = run_in_folder(nqc.path, {"undeclared.nqc", "-api"});
  EXPECT_EQ(o.exit_code, 243);
  EXPECT_EQ(o.out, "");
}

}  // namespace

namespace {

// Binary bytes given as source: nqc (and this mode before) printed them back
// as the "source line" of a syntax error, a screen of control characters.
TEST(NqcMode, ABinaryFileIsOneErrorNotAScreenOfItsBytes) {
  TempDir d;
  std::string file = d.write("bin.nqc", std::string("\x7f\x01\x00\x02\x1b[2J", 8));
  auto r = run_rcxc({"nqc", file});
  EXPECT_EQ(r.exit_code, 243) << r.err;
  EXPECT_NE(r.err.find("# Error: '" + file + "' is not NQC source: it holds binary data"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\x1b'), std::string::npos) << r.err;
}

}  // namespace

namespace {

// An output named on the command line that is the program itself: nqc (and
// this mode before) opened -E for writing and emptied the source.
TEST(NqcMode, AnOutputThatIsTheSourceIsRefusedAndTheSourceKept) {
  const std::string source = "task main()\n{\n  On(OUT_A);\n}\n";
  for (const char* option : {"-E", "-L", "-O", "-R"}) {
    TempDir d;
    std::string file = d.write("p.nqc", source);
    auto r = run_rcxc({"nqc", option + file, file});
    EXPECT_EQ(r.exit_code, 244) << option << ": " << r.err;
    EXPECT_NE(r.err.find("refusing to write " + file + " (" + option + "): it is the source file"), std::string::npos)
        << r.err;
    EXPECT_EQ(rcxc::test::read_text_file(file), source) << option;
  }
}

// -O and -L naming one file kept only the listing, which overwrote the image.
TEST(NqcMode, TwoOutputsInOneFileAreRefused) {
  TempDir d;
  std::string file = d.write("p.nqc", "task main()\n{\n  On(OUT_A);\n}\n");
  auto r = run_rcxc({"nqc", "-O" + d.path + "/p.rcx", "-L" + d.path + "/./p.rcx", file});
  EXPECT_EQ(r.exit_code, 244) << r.err;
  EXPECT_NE(r.err.find("-L and -O both name " + d.path + "/p.rcx"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d.path + "/p.rcx"));
  auto e = run_rcxc({"nqc", "-E" + d.path + "/out", "-R" + d.path + "/out", file});
  EXPECT_EQ(e.exit_code, 244) << e.err;
}

// As nqc, an -R file that cannot be written stops the call before the tower
// is opened (before, the datalog was uploaded and then lost, exit 0).
TEST(NqcMode, AnRFileThatCannotBeWrittenIsAUsageError) {
  TempDir d;
  for (const std::string& bad : {d.path, d.path + "/no/such/folder/log.txt"}) {
    auto r = run_rcxc({"nqc", "-S/dev/no-such-tower", "-R" + bad, "-datalog"});
    EXPECT_EQ(r.exit_code, 244) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("cannot write the output file '" + bad + "' (-R)"), std::string::npos) << r.err;
  }
}

}  // namespace
