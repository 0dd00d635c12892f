// The command line is a contract for scripts and IDEs: exit codes and where
// usage text goes are checked end to end against the real binary.
#include <gtest/gtest.h>

#include "tests/support/process.h"

using rcxc::test::run_rcxc;

TEST(Cli, VersionPrintsNameAndVersion) {
  auto r = run_rcxc({"--version"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out.rfind("rcxc ", 0), 0u) << r.out;
}

TEST(Cli, HelpListsSubcommands) {
  auto r = run_rcxc({"--help"});
  EXPECT_EQ(r.exit_code, 0);
  for (const char* sub : {"compile", "run", "disasm"}) EXPECT_NE(r.out.find(sub), std::string::npos) << sub;
}

TEST(Cli, UnknownOptionIsUsageErrorOnStderr) {
  auto r = run_rcxc({"--no-such-option"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(r.err.find("--no-such-option"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Usage"), std::string::npos) << r.err;
}

TEST(Cli, UnknownSubcommandOptionShowsThatSubcommandsUsage) {
  auto r = run_rcxc({"run", "--bogus", "x.rcx"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("run"), std::string::npos) << r.err;
}

TEST(Cli, MissingSubcommandIsUsageError) {
  auto r = run_rcxc({});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("Usage"), std::string::npos);
}
