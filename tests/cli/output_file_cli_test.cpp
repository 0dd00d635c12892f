// Where `rcxc compile` writes: outputs were written beside their path and
// renamed over it, so `-o /dev/null` (run as root) replaced the device, and
// `--listing /dev/stderr` replaced the link, with regular files. Devices,
// pipes and links are now written through; these tests use a FIFO and links
// in a temporary folder, never the real /dev.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "link/transport.h"
#include "tests/support/process.h"

using rcxc::test::run_rcxc;
using rcxc::test::TempDir;

namespace {

const char* kProgram = "task main() { On(OUT_A); }\n";

TEST(OutputFileCli, AFifoStaysAFifoAndReceivesTheImage) {
  TempDir d;
  std::string fifo = d.path + "/out.rcx";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  // A reader first, so the compiler's open for writing does not wait.
  int reader = open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(reader, 0);
  auto r = run_rcxc({"compile", d.write("p.nqc", kProgram), "-o", fifo}, "", 10'000);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(std::filesystem::symlink_status(fifo).type(), std::filesystem::file_type::fifo);
  char head[4] = {};
  EXPECT_EQ(read(reader, head, sizeof head), 4);
  close(reader);
  EXPECT_EQ(std::string(head, 4), "RCXI");  // the .rcx signature
}

TEST(OutputFileCli, ALinkIsWrittenThroughAndStaysALink) {
  TempDir d;
  std::string target = d.write("real.rcx", "old");
  std::string link = d.path + "/link.rcx";
  std::filesystem::create_symlink(target, link);
  auto r = run_rcxc({"compile", d.write("p.nqc", kProgram), "-o", link});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::is_symlink(link));
  auto bytes = d.read("real.rcx");
  ASSERT_GE(bytes.size(), 4u);
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "RCXI");
}

TEST(OutputFileCli, AListingThroughALinkToStandardErrorArrivesThere) {
  TempDir d;
  std::string link = d.path + "/err";
  std::filesystem::create_symlink("/proc/self/fd/2", link);
  auto r = run_rcxc({"compile", d.write("p.nqc", kProgram), "-o", d.path + "/p.rcx", "--listing", link});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::is_symlink(link));
  EXPECT_NE(r.err.find("task 0 main"), std::string::npos) << r.err;
}

TEST(OutputFileCli, ADirectoryIsNotWritable) {
  TempDir d;
  std::filesystem::create_directory(d.path + "/out");
  auto r = run_rcxc({"compile", d.write("p.nqc", kProgram), "-o", d.path + "/out"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cannot write " + d.path + "/out"), std::string::npos) << r.err;
}

// "cannot write X" said no more: a missing folder, a folder named as the
// file and a full disk read alike. The reason now follows, for every output.
TEST(OutputFileCli, AFailedWriteSaysWhy) {
  TempDir d;
  std::string src = d.write("p.nqc", kProgram);
  std::filesystem::create_directory(d.path + "/out");
  const std::pair<std::vector<std::string>, std::string> cases[] = {
      {{"compile", src, "-o", d.path + "/out"}, d.path + "/out: Is a directory"},
      {{"compile", src, "-o", d.path + "/no/p.rcx"}, d.path + "/no/p.rcx: No such file or directory"},
      {{"compile", src, "--listing=" + d.path + "/no/p.lst"}, "p.lst: No such file or directory"},
      {{"compile", "-E", src, "-o", d.path + "/out"}, "/out: Is a directory"},
      {{"run", src, "--trace", d.path + "/no/t.vcd"}, "t.vcd: No such file or directory"},
      {{"nqc", "-Trcx", "-O" + d.path + "/out", src}, "/out: Is a directory"},
  };
  for (const auto& [args, reason] : cases) {
    auto r = run_rcxc(args);
    EXPECT_NE(r.exit_code, 0) << args[0];
    EXPECT_NE(r.err.find("cannot write"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(reason), std::string::npos) << r.err;
  }
}

// A listing that could not be written failed the compile with a fresh
// image in place, which make then took for built: no image is written.
TEST(OutputFileCli, AFailedListingLeavesNoImage) {
  TempDir d;
  std::string src = d.write("p.nqc", kProgram);
  auto missing = run_rcxc({"compile", src, "-o", d.path + "/p.rcx", "--listing=" + d.path + "/no/p.lst"});
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("p.lst: No such file or directory"), std::string::npos) << missing.err;
  EXPECT_FALSE(std::filesystem::exists(d.path + "/p.rcx"));
  if (std::filesystem::exists("/dev/full")) {
    std::filesystem::create_symlink("/dev/full", d.path + "/full.lst");
    auto full = run_rcxc({"compile", src, "--listing=" + d.path + "/full.lst"});
    EXPECT_EQ(full.exit_code, 1);
    EXPECT_NE(full.err.find("full.lst: No space left on device"), std::string::npos) << full.err;
    EXPECT_FALSE(std::filesystem::exists(d.path + "/p.rcx"));  // FILE.rcx, the default
  }
  // Both written when both can be.
  auto both = run_rcxc({"compile", src, "--listing=" + d.path + "/p.lst"});
  EXPECT_EQ(both.exit_code, 0) << both.err;
  EXPECT_TRUE(std::filesystem::exists(d.path + "/p.rcx"));
  EXPECT_TRUE(std::filesystem::exists(d.path + "/p.lst"));
}

TEST(OutputFileCli, NoPredictableTemporaryALinkCouldRedirect) {
  // The temporary was "OUT.rcxc-tmp": a link planted there made the
  // compiler write through it into any file the user could write.
  TempDir d;
  std::string victim = d.write("victim.txt", "precious\n");
  std::filesystem::create_symlink(victim, d.path + "/p.rcx.rcxc-tmp");
  auto r = run_rcxc({"compile", d.write("p.nqc", kProgram), "-o", d.path + "/p.rcx"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  auto kept = d.read("victim.txt");
  EXPECT_EQ(std::string(kept.begin(), kept.end()), "precious\n");
  EXPECT_TRUE(std::filesystem::is_symlink(d.path + "/p.rcx.rcxc-tmp"));
  // The image is a plain file with the usual mode for new files.
  struct stat st{};
  ASSERT_EQ(stat((d.path + "/p.rcx").c_str(), &st), 0);
  mode_t mask = umask(0);
  umask(mask);
  EXPECT_EQ(st.st_mode & 0777, 0666 & ~mask);
}

TEST(OutputFileCli, AnImageAndAListingOfTheSameNameAreRefused) {
  TempDir d;
  std::string src = d.write("p.nqc", kProgram);
  auto r = run_rcxc({"compile", src, "-o", d.path + "/out", "--listing=" + d.path + "/./out"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("the image and the listing would both be written to"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(d.path + "/out"));
}

TEST(OutputFileCli, ATraceOverTheInputImageIsRefused) {
  TempDir d;
  ASSERT_EQ(run_rcxc({"compile", d.write("p.nqc", kProgram), "-o", d.path + "/img.json"}).exit_code, 0);
  auto before = d.read("img.json");
  auto r = run_rcxc({"run", d.path + "/img.json", "--trace", d.path + "/img.json"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("refusing to write the trace to " + d.path + "/img.json: it is the input"), std::string::npos)
      << r.err;
  EXPECT_EQ(d.read("img.json"), before);
}

// The program's own `// @scenario` file is an input as --scenario's is: a
// trace of the same name replaced it with the trace.
TEST(OutputFileCli, ATraceOverTheSourcesScenarioFileIsRefused) {
  TempDir d;
  const std::string scenario = "[[input]]\nat_ms = 5\nmessage = 3\n";
  d.write("s.json", scenario);
  std::string src = d.write("p.nqc", std::string(kProgram) + "// @scenario s.json\n");
  for (const std::string& trace : {d.path + "/s.json", d.path + "/./s.json"}) {
    auto r = run_rcxc({"run", src, "--trace", trace});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("refusing to write the trace to " + trace + ": it is the input " + d.path + "/s.json"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(rcxc::test::read_text_file(d.path + "/s.json"), scenario);
  }
}

// --listing's value is optional: `--listing prog.nqc` takes the program as
// the listing's name, and the message says so instead of only that the
// source is missing; nothing is written.
TEST(OutputFileCli, AListingThatTookTheSourceSaysSo) {
  TempDir d;
  std::string src = d.write("p.nqc", kProgram);
  auto r = run_rcxc({"compile", "--listing", src});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--listing took " + src), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--listing=FILE"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(d.path + "/p.rcx"));
  std::ifstream in(src);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), kProgram);
  auto none = run_rcxc({"compile"});
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("no source file"), std::string::npos) << none.err;
  // The listing after the source works.
  auto ok = run_rcxc({"compile", src, "-o", d.path + "/p.rcx", "--listing"});
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("task"), std::string::npos);
}

}  // namespace

// A listing, a disassembly, a report or help printed to a full disk used to
// end with exit 0 and nothing (or half) in the file.
TEST(OutputFileCli, AStandardOutputThatCannotBeWrittenIsAFailure) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  TempDir d;
  std::string src = d.write("p.nqc", kProgram);
  const std::string quoted = "'" + src + "'";
  const std::vector<std::string> commands = {"disasm " + quoted,
                                             "run " + quoted + " --report json",
                                             "compile " + quoted + " --listing -o '" + d.path + "/p.rcx'",
                                             "compile -E " + quoted,
                                             "nqc -Trcx -L " + quoted,
                                             "help"};
  for (const std::string& command : commands) {
    auto r = rcxc::test::run_process({"/bin/sh", "-c", "'" RCXC_BINARY "' " + command + " > /dev/full"});
    // nqc mode ends with nqc's 243, as for an -R file that cannot take the
    // text (docs/nqc.md); it ended with 1, which nqc never returns.
    EXPECT_EQ(r.exit_code, command.starts_with("nqc ") ? 243 : 1) << command << ": " << r.err;
    EXPECT_NE(r.err.find("rcxc: cannot write the standard output"), std::string::npos) << command << ": " << r.err;
  }
  // Written in full, the same commands succeed.
  EXPECT_EQ(rcxc::test::run_process({"/bin/sh", "-c", "'" RCXC_BINARY "' disasm '" + src + "' > /dev/null"}).exit_code,
            0);
}

// `-o -` on a terminal wrote the image's bytes to it (exit 0): garbage on
// the screen, and an escape sequence among them acted on. The same to a
// pipe or a file still works.
TEST(OutputFileCli, AnImageIsNotWrittenToATerminal) {
  auto opened = rcx::open_pty();
  ASSERT_TRUE(std::holds_alternative<rcx::Pty>(opened)) << std::get<rcx::TransportError>(opened).message;
  auto& pty = std::get<rcx::Pty>(opened);
  TempDir d;
  std::string src = d.write("p.nqc", kProgram);
  auto r = rcxc::test::run_process(
      {"/bin/sh", "-c", "'" RCXC_BINARY "' compile '" + src + "' -o - > '" + pty.slave_path + "'"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err, "rcxc compile: -o - would write the binary image to the terminal: send the standard output to a "
                   "file or a pipe, or name the image with -o FILE\n");
  auto named = run_rcxc({"compile", src, "-o", pty.slave_path});
  EXPECT_EQ(named.exit_code, 2) << named.err;
  EXPECT_NE(named.err.find("-o " + pty.slave_path + " would write the binary image to the terminal"), std::string::npos)
      << named.err;
  rcx::close_pty(pty);
  auto piped = run_rcxc({"compile", src, "-o", "-"});
  EXPECT_EQ(piped.exit_code, 0) << piped.err;
  EXPECT_EQ(piped.out.substr(0, 4), "RCXI");
}

// A reader that leaves before the output is written (`... | head -c1`):
// rcxc was killed by SIGPIPE (exit 141, not a word) or, when the write came
// at the end, ended 1 with the message: now always the latter. The output
// is larger than a pipe holds, so the write meets the closed pipe whenever
// the reader closes it.
TEST(OutputFileCli, AReaderThatLeavesEarlyIsAFailureWithAMessage) {
  TempDir d;
  std::string lines = "int x;\ntask main() {\n";
  for (int i = 0; i < 20000; ++i) lines += "  x = " + std::to_string(i) + ";\n";
  std::string src = d.write("long.nqc", lines + "}\n");
  for (const std::string& command : {"format '" + src + "'", "compile -E -n '" + src + "'"}) {
    // rcxc's exit status goes to stderr: the pipeline's own is the reader's.
    auto status = rcxc::test::run_process(
        {"/bin/sh", "-c", "{ '" RCXC_BINARY "' " + command + "; echo \"exit $?\" >&2; } | { exec 0<&-; sleep 1; }"});
    EXPECT_NE(status.err.find("rcxc: cannot write the standard output"), std::string::npos) << command << ": " << status.err;
    EXPECT_NE(status.err.find("exit 1\n"), std::string::npos) << command << ": " << status.err;
  }
}

// -E printed to the standard output whatever -o said, and took --listing
// without a word: `rcxc compile -E p.nqc -o p.i` left no p.i. It writes to
// -o as gcc -E does, refuses the source file there, and refuses a listing.
TEST(OutputFileCli, PreprocessedTextGoesToTheOutputFile) {
  TempDir d;
  std::string src = d.write("p.nqc", "#define POWER 5\ntask main() { SetPower(OUT_A, POWER); }\n");
  auto r = run_rcxc({"compile", "-E", "-n", src, "-o", d.path + "/p.i"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_NE(rcxc::test::read_text_file(d.path + "/p.i").find("SetPower(OUT_A, 5);"), std::string::npos);
  auto over_source = run_rcxc({"compile", "-E", src, "-o", src});
  EXPECT_EQ(over_source.exit_code, 2) << over_source.err;
  EXPECT_NE(rcxc::test::read_text_file(src).find("#define POWER 5"), std::string::npos);
  auto listing = run_rcxc({"compile", "-E", src, "--listing=" + d.path + "/p.lst"});
  EXPECT_EQ(listing.exit_code, 2) << listing.err;
  EXPECT_NE(listing.err.find("leave out --listing"), std::string::npos) << listing.err;
}

namespace {

// `rcxc format -i` on a source reached through a symbolic link wrote through
// the link: under a file-size limit the source was cut to 4 KiB of the new
// text while rcxc said "it is left as it was". The file behind the link is
// now replaced as a plain file is, and the link stays.
std::string big_source() {
  std::string text = "task main(){\n";
  for (int i = 0; i < 300; ++i) text += "On(OUT_A);Off(OUT_A);\n";
  return text + "}\n";
}

rcxc::test::ProcessResult rcxc_under_file_limit(const std::string& args, bool ignore_signal) {
  // ulimit -f counts 512- or 1024-byte blocks: 4 blocks are at most 4 KiB.
  std::string trap = ignore_signal ? "trap '' XFSZ; " : "";
  return rcxc::test::run_process({"/bin/sh", "-c", trap + "ulimit -f 4 && exec " RCXC_BINARY " " + args}, "", 20'000);
}

TEST(OutputFileCli, AFailedFormatThroughALinkLeavesTheSourceWhole) {
  TempDir d;
  std::string text = big_source();
  std::string real = d.write("real.nqc", text);
  std::string link = d.path + "/link.nqc";
  std::filesystem::create_symlink("real.nqc", link);
  auto r = rcxc_under_file_limit("format -i " + link, true);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("cannot write " + link + ": File too large; it is left as it was"), std::string::npos) << r.err;
  EXPECT_EQ(rcxc::test::read_text_file(real), text);
  EXPECT_TRUE(std::filesystem::is_symlink(link));
  // Without a limit the file behind the link is formatted; the link stays.
  auto ok = run_rcxc({"format", "-i", link});
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_TRUE(std::filesystem::is_symlink(link));
  EXPECT_EQ(rcxc::test::read_text_file(real).rfind("task main()\n{\n  On(OUT_A);\n", 0), 0u);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(d.path), std::filesystem::directory_iterator()), 2);
}

// The file-size signal killed rcxc mid-write (exit 153) and left its
// temporary beside the output; the write now fails with a message.
TEST(OutputFileCli, AFileSizeLimitIsAFailedWriteNotAKill) {
  TempDir d;
  std::string src = d.write("p.nqc", big_source());
  auto r = rcxc_under_file_limit("compile " + src + " -E -o " + d.path + "/out.i", false);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("cannot write " + d.path + "/out.i: File too large"), std::string::npos) << r.err;
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(d.path), std::filesystem::directory_iterator()), 1);
}

}  // namespace

namespace {

// A name of 250 characters is a good name, but ".NAME.XXXXXX" is not: the
// temporary could not be made ("File name too long").
TEST(OutputFileCli, ALongButValidNameCanBeWritten) {
  TempDir d;
  std::string out = d.path + "/" + std::string(246, 'a') + ".rcx";
  auto r = run_rcxc({"compile", d.write("p.nqc", kProgram), "-o", out});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::is_regular_file(out));
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(d.path), std::filesystem::directory_iterator()), 2);
}

}  // namespace
