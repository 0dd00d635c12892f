// nqc's whole RCX API against rcxc: every function, macro and constant that
// `nqc -Trcx -api` prints (read from nqc at test time, never kept here) is
// used in a small program; each program nqc compiles must compile with rcxc
// and run the same on the emulator. Names nqc refuses for the RCX (those of
// its other targets) are skipped. Names with a leading underscore count too:
// programs use `_SENSOR_CFG`, `_init` and asm's flags, which rcxc lacked
// while this test passed them over. Skipped when nqc is absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "backend/compile.h"
#include "rcx/image.h"
#include "runtime/vm.h"
#include "tests/support/process.h"
#include "verify/compare.h"

namespace rcxc {
namespace {

// One way of using a name; a name may have several (value, then statement).
struct Use {
  std::string name;
  std::vector<std::string> bodies;  // statements for task main, tried in order
};

std::string argument_list(std::size_t count, const std::string& params) {
  // One argument per parameter, fitting its kind: a sensor for `__sensor`,
  // the variable `v` for `int &`, the number 1 otherwise.
  std::vector<std::string> kinds;
  std::string cur;
  for (char c : params + ",") {
    if (c == ',') {
      kinds.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  std::string out;
  for (std::size_t i = 0; i < count; ++i) {
    const std::string& k = i < kinds.size() ? kinds[i] : std::string();
    std::string arg = "1";
    if (k.find("__sensor") != std::string::npos) arg = "SENSOR_1";
    else if (k.find('&') != std::string::npos && k.find("const") == std::string::npos) arg = "v";
    out += (i ? ", " : "") + arg;
  }
  return out;
}

std::size_t count_params(const std::string& params) {
  if (params.find_first_not_of(" \t\n") == std::string::npos) return 0;
  return static_cast<std::size_t>(std::count(params.begin(), params.end(), ',')) + 1;
}

std::vector<Use> uses_of(const std::string& api) {
  std::map<std::string, Use> uses;
  auto add = [&](const std::string& name, std::vector<std::string> bodies) {
    if (name.empty() || uses.count(name)) return;
    uses[name] = Use{name, std::move(bodies)};
  };
  static const std::regex define(R"(^[ \t]*#[ \t]*define[ \t]+(\w+)(\(([^)]*)\))?)");
  static const std::regex function(R"(\bvoid[ \t\n]+(\w+)[ \t\n]*\(([^)]*)\))");
  std::size_t start = 0;
  while (start < api.size()) {
    std::size_t end = api.find('\n', start);
    if (end == std::string::npos) end = api.size();
    std::string line = api.substr(start, end - start);
    std::smatch m;
    if (std::regex_search(line, m, define)) {
      std::string name = m[1];
      if (m[2].matched) {
        std::string call = name + "(" + argument_list(count_params(m[3]), "") + ")";
        add(name, {"v = " + call + ";", call + ";"});
      } else {
        add(name, {"v = " + name + ";", name + ";"});
      }
    }
    start = end + 1;
  }
  for (auto it = std::sregex_iterator(api.begin(), api.end(), function); it != std::sregex_iterator(); ++it) {
    std::string name = (*it)[1], params = (*it)[2];
    if (params.find_first_not_of(" \t\n") != std::string::npos && params.find("void") != std::string::npos)
      params.clear();
    add(name, {name + "(" + argument_list(count_params(params), params) + ");"});
  }
  // Predefined macros, which -api does not print.
  uses["__NQC__"] = Use{"__NQC__", {"v = __NQC__;"}};
  uses["__RCX"] = Use{"__RCX", {"v = __RCX;"}};
  std::vector<Use> out;
  for (auto& [name, use] : uses) out.push_back(std::move(use));
  return out;
}

std::string program(const std::string& body) { return "int v;\ntask main()\n{\n  " + body + "\n  v += 0;\n}\n"; }

// A run as `rcxc compare` makes it: 10 us per instruction, no inputs.
rcx::Machine run(const rcx::Image& image) {
  rcx::Config config;
  config.instruction_cost_us = 10;
  rcx::Machine m(config);
  EXPECT_FALSE(m.load(0, image).has_value());
  m.start_program();
  m.run(5'000 * rcx::kMicrosPerMs);
  return m;
}

TEST(NqcApi, EveryNameOfNqcsRcxApiCompilesAndRunsAsNqcsCodeDoes) {
  std::string nqc = test::find_nqc();
  if (nqc.empty()) GTEST_SKIP() << "nqc is not installed";
  auto api = test::run_process({nqc, "-Trcx", "-api"});
  ASSERT_EQ(api.exit_code, 0);
  auto uses = uses_of(api.out);
  ASSERT_GT(uses.size(), 100u) << "nqc -api printed too little to parse";

  test::TempDir dir;
  std::vector<std::string> lacking, differing;
  std::set<std::string> checked;
  for (const auto& use : uses) {
    for (const auto& body : use.bodies) {
      std::string text = program(body);
      std::string src = dir.write("api.nqc", text), image_path = dir.path + "/api.rcx";
      if (test::run_process({nqc, "-Trcx", "-O" + image_path, src}).exit_code != 0) continue;
      auto theirs = rcx::read_image_file(image_path);
      ASSERT_TRUE(std::holds_alternative<rcx::Image>(theirs)) << body;
      checked.insert(use.name);
      SourceManager sm;
      Diagnostics diags;
      ir::Log log;
      auto ours = backend::compile_source("api.nqc", text, frontend::Options{}, ir::OptLevel::Os, sm, diags, log);
      if (!ours || diags.has_errors()) {
        std::string why;
        for (const auto& d : diags.all())
          if (d.severity == Severity::Error) {
            why = d.message;
            break;
          }
        lacking.push_back(use.name + " (`" + body + "`: " + why + ")");
        break;
      }
      const auto& their_image = std::get<rcx::Image>(theirs);
      auto a = run(ours->image), b = run(their_image);
      auto cmp = rcx::compare_runs({&a, &ours->image, "rcxc"}, {&b, &their_image, "nqc"});
      // `v` is global 0 in both images: its value is what a constant means.
      if (!cmp.same || a.state().vars[0] != b.state().vars[0])
        differing.push_back(use.name + " (`" + body + "`: v is " + std::to_string(a.state().vars[0]) + " with rcxc, " +
                            std::to_string(b.state().vars[0]) + " with nqc)\n" + cmp.side_by_side);
      break;
    }
  }
  std::string lacking_list, differing_list;
  for (const auto& l : lacking) lacking_list += "  " + l + "\n";
  for (const auto& d : differing) differing_list += "  " + d + "\n";
  EXPECT_TRUE(lacking.empty()) << lacking.size() << " names of nqc's RCX API that rcxc lacks:\n" << lacking_list;
  EXPECT_TRUE(differing.empty()) << differing.size() << " names that behave differently:\n" << differing_list;
  EXPECT_GT(checked.size(), 80u) << "nqc accepted too few of its own names";
}

// Arguments outside what the API's constants spell still make the bytes
// nqc's code has: the outputs and the mode of SetOutput and SetDirection
// share a byte and are added (SetDirection(OUT_A, 3) is output C reversed),
// and SetSensor's type is the config's high byte even when it is negative.
TEST(NqcApi, EdgeArgumentsMakeTheBytesNqcsCodeHas) {
  std::string nqc = test::find_nqc();
  if (nqc.empty()) GTEST_SKIP() << "nqc is not installed";
  const char* bodies[] = {
      "SetDirection(OUT_A, 3);", "SetOutput(OUT_A, OUT_ON + 1);", "SetOutput(OUT_B, 5);",
      "SetSensor(SENSOR_2, -300);", "SetSensor(SENSOR_1, -1);", "SetSensor(SENSOR_3, 0x3ff);",
  };
  test::TempDir dir;
  for (const char* body : bodies) {
    std::string text = std::string("#pragma noinit\ntask main()\n{\n  ") + body + "\n}\n";
    std::string src = dir.write("edge.nqc", text), image_path = dir.path + "/edge.rcx";
    ASSERT_EQ(test::run_process({nqc, "-Trcx", "-O" + image_path, src}).exit_code, 0) << body;
    auto theirs = rcx::read_image_file(image_path);
    ASSERT_TRUE(std::holds_alternative<rcx::Image>(theirs)) << body;
    SourceManager sm;
    Diagnostics diags;
    ir::Log log;
    auto ours = backend::compile_source("edge.nqc", text, frontend::Options{}, ir::OptLevel::Os, sm, diags, log);
    ASSERT_TRUE(ours && !diags.has_errors()) << body;
    const auto* mine = ours->image.find(rcx::FragmentType::Task, 0);
    const auto* nqcs = std::get<rcx::Image>(theirs).find(rcx::FragmentType::Task, 0);
    ASSERT_TRUE(mine && nqcs) << body;
    EXPECT_EQ(mine->code, nqcs->code) << body;
  }
}

}  // namespace
}  // namespace rcxc
