// `rcxc test --junit FILE`: the results as a JUnit XML report, the format CI
// services (GitLab, Jenkins, GitHub actions' test reporters) and grading
// scripts read. One <testcase> per test program; its failures, each with
// the line they name, in one <failure>; a path that could not be read is
// an <error>.
#pragma once

#include <string>
#include <vector>

#include "verify/testspec.h"

namespace rcx::semtest {

struct JUnitCase {
  std::string file;               // the test program's path, as given or found
  std::vector<Failure> failures;  // empty: passed
  double seconds = 0;             // compiling and running it
  std::string error;              // non-empty: it could not be run at all
};

// The report: well-formed XML 1.0 whatever the paths and messages hold
// (markup characters escaped; control characters and bytes that are not
// UTF-8 replaced by U+FFFD).
std::string junit_xml(const std::vector<JUnitCase>& cases);

}  // namespace rcx::semtest
