// A program compiled with the stdlib read once (frontend/stdlib_cache.h,
// what the fuzz targets use) must give what reading rcx.nqh each time gives: the
// same image byte for byte, and the same diagnostics, for the examples,
// random programs and programs with errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "backend/compile.h"
#include "frontend/stdlib_cache.h"
#include "ir/lower.h"
#include "rcx/image.h"
#include "tests/support/process.h"
#include "tests/support/random_programs.h"

using namespace rcxc;

namespace {

struct Outcome {
  std::vector<std::uint8_t> image;
  std::string diagnostics;
};

Outcome compile(const std::string& text, const frontend::Options& options, const frontend::StdlibCache* stdlib) {
  SourceManager sm;
  Diagnostics diags;
  ir::Log log;
  Outcome o;
  if (auto program = frontend::parse_source("p.nqc", text, options, stdlib, sm, diags))
    if (auto lowered = ir::lower(*program, diags))
      if (auto out = backend::compile(std::move(*lowered), ir::OptLevel::Os, diags, log))
        o.image = rcx::write_image(out->image);
  for (const auto& d : diags.all()) o.diagnostics += render_text(d, sm) + "\n";
  return o;
}

void expect_same_with_cache(const std::string& text, const std::string& what) {
  static const auto stdlib = frontend::make_stdlib_cache({});
  ASSERT_NE(stdlib, nullptr);
  Outcome a = compile(text, {}, nullptr);
  Outcome b = compile(text, {}, stdlib.get());
  EXPECT_EQ(a.image, b.image) << what;
  EXPECT_EQ(a.diagnostics, b.diagnostics) << what;
}

}  // namespace

TEST(StdlibCache, ExamplesCompileTheSame) {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(RCXC_SOURCE_DIR) + "/examples")) {
    if (entry.path().extension() != ".nqc") continue;
    expect_same_with_cache(test::read_text_file(entry.path().string()), entry.path().string());
    ++n;
  }
  EXPECT_GT(n, 5);
}

TEST(StdlibCache, RandomProgramsCompileTheSame) {
  for (unsigned seed = 1; seed <= 40; ++seed) {
    test::Generator g(seed);
    expect_same_with_cache(g.program(), "seed " + std::to_string(seed));
  }
}

TEST(StdlibCache, ErrorsAndWarningsAreTheSame) {
  for (const char* text : {
           "task main() { OnFwd(OUT_D); }\n",
           "task main() { x = 1; }\n",
           "task main() { SetSensor(SENSOR_4, SENSOR_TOUCH); }\n",
           "#define OUT_A 3\ntask main() { On(OUT_A); }\n",
           "int x; task main() { int y; if (x = 2) Wait(1); }\n",
           "task main() { PlaySound(SOUND_CLICK) }\n",
       })
    expect_same_with_cache(text, text);
}

TEST(StdlibCache, OtherDefinesReadTheStdlibAsUsual) {
  // Made without -D: with one, the stdlib is read again, as -D may change it.
  const std::string text = "task main() { On(LIMIT); }\n";
  frontend::Options options;
  options.define("LIMIT=OUT_B");
  auto stdlib = frontend::make_stdlib_cache({});
  Outcome a = compile(text, options, nullptr);
  Outcome b = compile(text, options, stdlib.get());
  EXPECT_FALSE(a.image.empty()) << a.diagnostics;
  EXPECT_EQ(a.image, b.image);
  frontend::Options none;
  none.no_stdlib = true;
  EXPECT_EQ(frontend::make_stdlib_cache(none), nullptr);
}
