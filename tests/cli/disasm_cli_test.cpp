// `rcxc disasm` end to end on hand-built images.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "rcx/image.h"
#include "tests/support/process.h"

using rcxc::test::run_rcxc;

namespace {

std::string write_temp(const std::string& dir, const std::vector<std::uint8_t>& bytes) {
  std::string p = dir + "/d.rcx";
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return p;
}

}  // namespace

TEST(DisasmCli, ListsTasksAndSubsWithAddressesMnemonicsOperandsBytes) {
  rcx::Image img;
  // task 0: set var[0] = 5; chk 10 >= var[0] -> 18 (the offset field is at 11, +7); jmp back to 0.
  img.fragments.push_back({rcx::FragmentType::Task, 0,
                           {0x14, 0x00, 0x02, 0x05, 0x00,                     //  0 set var[0], 5
                            0x85, 0x42, 0x00, 0x0a, 0x00, 0x00, 0x07,         //  5 chk 10 >= var[0], 18
                            0x27, 0x8d,                                       // 12 jmp 0 (13 - 0x8d + 128)
                            0x13, 0x05, 0x02, 0x03,                           // 14 pwr AC, 3
                            0x01}});                                          // 18 no opcode at all
  img.fragments.push_back({rcx::FragmentType::Subroutine, 2, {0x51, 0x03, 0xf6}});
  img.symbols.push_back({rcx::SymbolType::Task, 0, "main"});
  img.symbols.push_back({rcx::SymbolType::Subroutine, 2, "beep"});
  std::string dir = rcxc::test::make_temp_dir();
  auto r = run_rcxc({"disasm", write_temp(dir, rcx::write_image(img))});
  std::filesystem::remove_all(dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string& out = r.out;
  EXPECT_NE(out.find("task 0 main (19 bytes)"), std::string::npos) << out;
  EXPECT_NE(out.find("0000  set var[0], 5"), std::string::npos) << out;
  EXPECT_NE(out.find("14 00 02 05 00"), std::string::npos) << out;
  EXPECT_NE(out.find("0005  chk 10 >= var[0], 18"), std::string::npos) << out;
  EXPECT_NE(out.find("0012  jmp 0"), std::string::npos) << out;
  EXPECT_NE(out.find("0014  pwr AC, 3"), std::string::npos) << out;
  EXPECT_NE(out.find("0018  ??? 0x01"), std::string::npos) << out;
  EXPECT_NE(out.find("sub 2 beep (3 bytes)"), std::string::npos) << out;
  EXPECT_NE(out.find("0000  sound 3"), std::string::npos) << out;
  EXPECT_NE(out.find("0002  ret"), std::string::npos) << out;
}

TEST(DisasmCli, MotorCodesAreSpelledOut) {
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0, {0x21, 0x85, 0x21, 0x42, 0x21, 0x07, 0xe1, 0x87, 0xe1, 0x02, 0xe1, 0x41}});
  std::string dir = rcxc::test::make_temp_dir();
  auto r = run_rcxc({"disasm", write_temp(dir, rcx::write_image(img))});
  std::filesystem::remove_all(dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* line : {"out AC, on", "out B, off", "out ABC, float", "dir ABC, fwd", "dir B, rev", "dir A, flip"})
    EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
}

// An asm block can put a request in a program: it is named with its
// operands, as nqc -L names it, and marked as nothing the brick runs.
TEST(DisasmCli, RequestsInCodeAreNamedAndMarked) {
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0, {0xa4, 0x01, 0x00, 0x02, 0x00, 0x12, 0x09, 0x01, 0x10, 0xa4, 0x03}});
  std::string dir = rcxc::test::make_temp_dir();
  auto r = run_rcxc({"disasm", write_temp(dir, rcx::write_image(img))});
  std::filesystem::remove_all(dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* line : {"0000  logupload 1, 2  ; a request, not a program opcode a4 01 00 02 00",
                           "0005  getval sensor[1]  ; a request, not a program opcode 12 09 01",
                           "0008  alive  ; a request, not a program opcode 10",
                           "0009  logupload (truncated)  ; a request, not a program opcode a4 03"})
    EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
  EXPECT_EQ(r.out.find("???"), std::string::npos) << r.out;
}

TEST(DisasmCli, BadFileIsAClearError) {
  std::string dir = rcxc::test::make_temp_dir();
  auto r = run_rcxc({"disasm", write_temp(dir, {'R', 'C', 'X', 'I', 9, 9})});
  std::filesystem::remove_all(dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("rcxc disasm:"), std::string::npos);
  EXPECT_TRUE(r.out.empty());
}

// Found by the command-line property test: these aborted (uncaught
// std::ios_base::failure from reading a directory) with exit 134.
TEST(DisasmCli, DirectoryIsAnErrorNotACrash) {
  rcxc::test::TempDir d;
  for (const char* command : {"disasm", "run"}) {
    auto r = run_rcxc({command, d.path});
    EXPECT_EQ(r.exit_code, 1) << command << ": " << r.err;
    EXPECT_NE(r.err.find(d.path + ": is a directory, not a source file or an .rcx image"), std::string::npos)
        << command << ": " << r.err;
  }
}

// A folder named like a source was "not an .rcx image" to run, disasm and
// download, where compile says it is not a source file; a folder named .rcx
// is still "not an .rcx image".
TEST(DisasmCli, AFolderIsRefusedInTheWordsItsNameCallsFor) {
  rcxc::test::TempDir d;
  for (const char* name : {"/prog.nqc", "/LIB.NQH", "/prog.rcx"}) {
    std::string folder = d.path + name;
    std::filesystem::create_directory(folder);
    std::string kind = std::string(name).ends_with(".rcx") ? "an .rcx image" : "a source file";
    for (std::string command : {"disasm", "run", "download"}) {
      std::vector<std::string> args{command, folder};
      if (command == "download") args = {command, "--port", "/dev/no-such-tower", folder};
      auto r = run_rcxc(args);
      EXPECT_EQ(r.exit_code, 1) << command << " " << name << ": " << r.err;
      EXPECT_EQ(r.err, "rcxc " + command + ": " + folder + ": is a directory, not " + kind + "\n") << command;
    }
    if (kind == "a source file") {
      auto compiled = run_rcxc({"compile", folder});
      EXPECT_NE(compiled.err.find("is a directory, not a source file"), std::string::npos) << compiled.err;
    }
  }
}

// "-": the standard input, an image (by its signature) or NQC source, for
// disasm and run alike (both load programs the same way).
TEST(DisasmCli, TheStandardInputIsAnImageOrSource) {
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0, {0x51, 0x03}});  // sound 3
  img.symbols.push_back({rcx::SymbolType::Task, 0, "main"});
  auto bytes = rcx::write_image(img);
  auto image = run_rcxc({"disasm", "-"}, std::string(bytes.begin(), bytes.end()));
  ASSERT_EQ(image.exit_code, 0) << image.err;
  EXPECT_NE(image.out.find("0000  sound 3"), std::string::npos) << image.out;

  auto source = run_rcxc({"disasm", "-", "-n"}, "task main() { asm { 0x51, 2 }; }\n");
  ASSERT_EQ(source.exit_code, 0) << source.err;
  EXPECT_NE(source.out.find("sound 2"), std::string::npos) << source.out;

  auto ran = run_rcxc({"run", "-", "--for", "100"}, "task main() { PlaySound(SOUND_UP); }\n");
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  EXPECT_NE(ran.out.find("sound SOUND_UP"), std::string::npos) << ran.out;

  auto truncated = run_rcxc({"run", "-"}, std::string(bytes.begin(), bytes.end() - 1));
  EXPECT_EQ(truncated.exit_code, 1);
  EXPECT_NE(truncated.err.find("rcxc run: <stdin>: "), std::string::npos) << truncated.err;

  auto broken = run_rcxc({"run", "-"}, "task main() { Wait(1) }\n");
  EXPECT_EQ(broken.exit_code, 1);
  EXPECT_NE(broken.err.find("<stdin>:1:22: error"), std::string::npos) << broken.err;
  EXPECT_NE(broken.err.find("rcxc run: <stdin>: the program does not compile"), std::string::npos) << broken.err;
}

// Binary bytes that are no image were compiled as source from the standard
// input: a screen of errors quoting the bytes raw (a file of them was
// already refused in one line).
TEST(DisasmCli, BinaryBytesOnTheStandardInputAreOneError) {
  const std::string junk("\x7f\x01\x00\x02\x1b[2J\nmore\n", 12);
  for (const char* command : {"disasm", "run", "download"}) {
    auto r = run_rcxc({command, "-"}, junk);
    EXPECT_EQ(r.exit_code, 1) << command << ": " << r.err;
    EXPECT_EQ(r.err, std::string("rcxc ") + command + ": <stdin>: binary data, neither NQC source nor an .rcx image\n");
  }
}

// The same bytes in a file named prog.nqc (or prog, prog.txt) were read as
// an image by intent: "offset 0: not an RCX image (signature is not
// "RCXI")". Named .rcx, or starting "RCXI", they are still the image
// reader's to judge.
TEST(DisasmCli, BinaryBytesInAFileNotNamedAsAnImageAreOneError) {
  rcxc::test::TempDir d;
  const std::string junk("task main() {\n\0}\n", 17);
  for (const char* name : {"p.nqc", "p", "p.txt"}) {
    std::string path = d.write(name, junk);
    for (const char* command : {"disasm", "run", "download"}) {
      auto r = run_rcxc({command, path});
      EXPECT_EQ(r.exit_code, 1) << command << ": " << r.err;
      EXPECT_EQ(r.err,
                std::string("rcxc ") + command + ": " + path + ": binary data, neither NQC source nor an .rcx image\n");
    }
  }
  auto image = run_rcxc({"disasm", d.write("p.rcx", junk)});
  EXPECT_EQ(image.exit_code, 1);
  EXPECT_NE(image.err.find("not an RCX image (signature is not \"RCXI\")"), std::string::npos) << image.err;
}

// `rcxc run prog.rcx -O0 -DX` (or disasm, download) has nothing to compile:
// the options were taken and ignored without a word. A note says so; the
// command still does its work. Source given the same options gets no note.
TEST(DisasmCli, CompilerOptionsGivenWithAnImageGetANote) {
  rcxc::test::TempDir d;
  rcx::Image img;
  img.fragments.push_back({rcx::FragmentType::Task, 0, {0x13, 0x05, 0x02, 0x03}});
  std::string image = write_temp(d.path, rcx::write_image(img));
  for (const char* command : {"disasm", "run"}) {
    auto r = run_rcxc({command, image, "-O0", "-DX"});
    EXPECT_EQ(r.exit_code, 0) << command << ": " << r.err;
    EXPECT_NE(r.err.find("is an .rcx image: -I, -D, -U, -n and -O apply to NQC source and were not used"),
              std::string::npos)
        << command << ": " << r.err;
    EXPECT_EQ(run_rcxc({command, image}).err.find("were not used"), std::string::npos) << command;
  }
  auto source = run_rcxc({"disasm", d.write("p.nqc", "task main() {}\n"), "-O0"});
  EXPECT_EQ(source.exit_code, 0) << source.err;
  EXPECT_EQ(source.err.find("were not used"), std::string::npos) << source.err;
}
