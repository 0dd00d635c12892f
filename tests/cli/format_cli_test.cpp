// `rcxc format`: printing, --check and --in-place, with their exit codes,
// and files it refuses left as they were.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/process.h"

namespace rcxc::test {
namespace {

constexpr const char* kMessy = "task main() {\nOnFwd(OUT_A+OUT_C); Wait(50);\n}\n";
constexpr const char* kTidy = "task main()\n{\n  OnFwd(OUT_A + OUT_C);\n  Wait(50);\n}\n";

TEST(FormatCli, PrintsTheFormattedFile) {
  TempDir dir;
  auto r = run_rcxc({"format", dir.write("messy.nqc", kMessy)});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, kTidy);
  EXPECT_EQ(read_text_file(dir.path + "/messy.nqc"), kMessy);  // only printed
}

TEST(FormatCli, ReadsStandardInputForDashOrNoFile) {
  auto none = run_rcxc({"format"}, kMessy);
  EXPECT_EQ(none.exit_code, 0) << none.err;
  EXPECT_EQ(none.out, kTidy);
  auto dash = run_rcxc({"format", "-", "--indent", "4"}, "task main()\n{\nWait(1);\n}\n");
  EXPECT_EQ(dash.out, "task main()\n{\n    Wait(1);\n}\n");
}

// A folder with one file to format and one already formatted.
struct MessyAndTidy {
  TempDir dir;
  std::string messy = dir.write("messy.nqc", kMessy);
  std::string tidy = dir.write("tidy.nqc", kTidy);
};

TEST(FormatCli, CheckNamesTheFilesThatWouldChange) {
  auto [dir, messy, tidy] = MessyAndTidy{};
  auto r = run_rcxc({"format", "--check", tidy, messy});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out, messy + "\n");
  EXPECT_EQ(read_text_file(messy), kMessy);
  auto clean = run_rcxc({"format", "--check", tidy});
  EXPECT_EQ(clean.exit_code, 0);
  EXPECT_EQ(clean.out, "");
}

TEST(FormatCli, InPlaceRewritesOnlyWhatChanges) {
  auto [dir, messy, tidy] = MessyAndTidy{};
  auto r = run_rcxc({"format", "-i", messy, tidy});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(read_text_file(messy), kTidy);
  EXPECT_EQ(read_text_file(tidy), kTidy);
  EXPECT_EQ(run_rcxc({"format", "--check", messy}).exit_code, 0);
}

TEST(FormatCli, RefusedFilesAreLeftAsTheyWere) {
  TempDir dir;
  std::string broken = dir.write("broken.nqc", "task main() {\n  /* no end\n}\n");
  std::string messy = dir.write("messy.nqc", kMessy);
  auto r = run_rcxc({"format", "--in-place", broken, messy});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "rcxc format: " + broken +
                       ": cannot format: line 2, column 3: unterminated /* comment; the file is left as it was\n");
  EXPECT_EQ(read_text_file(broken), "task main() {\n  /* no end\n}\n");
  EXPECT_EQ(read_text_file(messy), kTidy);  // the other file is still formatted
  auto missing = run_rcxc({"format", dir.path + "/none.nqc"});
  EXPECT_EQ(missing.exit_code, 1);
  // With the reason, as compile and run give it: "cannot be opened" alone left
  // a misspelt name and a missing permission looking alike.
  EXPECT_EQ(missing.err, "rcxc format: " + dir.path + "/none.nqc: cannot open file: no such file\n");
}

// A file that begins with a UTF-8 byte-order mark compiles (the compiler
// drops the mark) but was refused: "stray character '\xef' in program".
// The text after the mark is formatted, and the mark kept.
TEST(FormatCli, AByteOrderMarkIsKeptAndWhatFollowsItFormatted) {
  TempDir dir;
  const std::string bom = "\xEF\xBB\xBF";
  auto messy = dir.write("bom.nqc", bom + kMessy);
  auto r = run_rcxc({"format", messy});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, bom + kTidy);
  auto tidy = dir.write("tidy.nqc", bom + kTidy);
  auto check = run_rcxc({"format", "--check", tidy});
  EXPECT_EQ(check.exit_code, 0) << check.err << check.out;
  EXPECT_EQ(run_rcxc({"format", "-i", messy}).exit_code, 0);
  EXPECT_EQ(read_text_file(messy), bom + kTidy);
  // A mark anywhere else is still refused, as one character (it was one
  // stray character per byte).
  auto inside = run_rcxc({"format", dir.write("inside.nqc", "int x;\n" + bom + "task main() {}\n")});
  EXPECT_EQ(inside.exit_code, 1);
  EXPECT_NE(inside.err.find("line 2, column 1: stray character U+FEFF (a byte-order mark, which only the start of a "
                            "file may hold): delete it\n"),
            std::string::npos)
      << inside.err;
}

TEST(FormatCli, BadCommandLines) {
  TempDir dir;
  std::string messy = dir.write("messy.nqc", kMessy);
  EXPECT_EQ(run_rcxc({"format", "-i", "--check", messy}).exit_code, 2);
  EXPECT_EQ(run_rcxc({"format", "-i"}, kMessy).exit_code, 2);
  EXPECT_EQ(run_rcxc({"format", "--indent", "0", messy}).exit_code, 2);
  EXPECT_EQ(run_rcxc({"format", "--indent", "9", messy}).exit_code, 2);
}

// `format - -` printed the text once and then nothing for the second '-'
// (the input was used up), with exit 0.
TEST(FormatCli, TheStandardInputTwiceIsAUsageError) {
  TempDir dir;
  std::string messy = dir.write("messy.nqc", kMessy);
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{{"format", "-", "-"}, {"format", "-", messy, "-", "--check"}}) {
    auto r = run_rcxc(args, kMessy);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_NE(r.err.find("'-' (the standard input) is given 2 times; it can be read once"), std::string::npos) << r.err;
  }
}

TEST(FormatCli, TooLargeIsRefused) {
  auto r = run_rcxc({"format", "-"}, std::string((1 << 20) + 1, ' '));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("larger than a source file may be (1 MiB)"), std::string::npos) << r.err;
}

// editors/vim's :RcxcFormat replaces the buffer with rcxc's output, and
// leaves a buffer rcxc refuses as it was (a :%! filter would not).
TEST(FormatCli, VimCommandFormatsTheBufferOrLeavesIt) {
  auto nvim = run_process({"/bin/sh", "-c", "command -v nvim"});
  if (nvim.exit_code != 0) GTEST_SKIP() << "nvim is not installed";
  TempDir dir;
  std::string messy = dir.write("messy.nqc", kMessy);
  std::string broken = dir.write("broken.nqc", "task main() {\n/* open\n");
  std::string bin = RCXC_BINARY;
  for (const std::string& file : {messy, broken}) {
    auto r = run_process({"/bin/sh", "-c",
                          "PATH=\"$0:$PATH\" exec nvim --headless -n -i NONE -u NONE --cmd \"set rtp^=$1\" "
                          "-c 'filetype plugin on' -c \"edit $2\" -c RcxcFormat -c 'write' -c 'qall!'",
                          bin.substr(0, bin.rfind('/')), RCXC_SOURCE_DIR "/editors/vim", file},
                         "", 60000);
    EXPECT_FALSE(r.timed_out);
  }
  EXPECT_EQ(read_text_file(messy), kTidy);
  EXPECT_EQ(read_text_file(broken), "task main() {\n/* open\n");
}

}  // namespace
}  // namespace rcxc::test
