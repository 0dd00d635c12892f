// The formatter's guarantee on real programs: every program of the corpus,
// the semantic tests, the examples and the random program generators
// compiles to the same bytes after formatting, and formatting the result
// again changes nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <variant>
#include <vector>

#include "backend/compile.h"
#include "format/format.h"
#include "rcx/image.h"
#include "tests/support/process.h"
#include "tests/support/random_programs.h"

namespace rcxc {
namespace {

namespace fs = std::filesystem;

std::string formatted(const std::string& text) {
  auto out = format::format_source(text);
  if (auto* r = std::get_if<format::Refusal>(&out)) {
    ADD_FAILURE() << "refused: " << r->message;
    return text;
  }
  return std::get<std::string>(out);
}

// The image bytes, or nullopt when the program does not compile. `path`
// names the text so its #includes are found beside it.
std::optional<std::vector<std::uint8_t>> image_of(const std::string& path, const std::string& text) {
  SourceManager sm;
  Diagnostics diags;
  ir::Log log;
  auto out = backend::compile_source(path, text, frontend::Options{}, ir::OptLevel::Os, sm, diags, log);
  if (!out) return std::nullopt;
  return rcx::write_image(out->image);
}

// Formatting keeps the image and is idempotent; returns whether it changed the text.
bool check_program(const std::string& path, const std::string& text) {
  std::string once = formatted(text);
  EXPECT_EQ(formatted(once), once) << path << ": formatting twice differs from once";
  auto before = image_of(path, text);
  auto after = image_of(path, once);
  EXPECT_EQ(before.has_value(), after.has_value()) << path << ": compiles before or after formatting only";
  if (before && after) {
    EXPECT_TRUE(*before == *after) << path << ": the image changed";
  }
  return once != text;
}

void check_folder(const fs::path& dir) {
  int changed = 0;
  auto files = test::nqc_programs_under(dir.string());
  for (const auto& f : files) changed += check_program(f, test::read_text_file(f)) ? 1 : 0;
  std::cout << dir.string() << ": " << files.size() << " programs, " << changed << " changed by formatting\n";
}

TEST(FormatPrograms, CorpusKeepsItsImages) {
  if (!fs::is_directory(RCXC_CORPUS_DIR)) GTEST_SKIP() << "no corpus at " << RCXC_CORPUS_DIR;
  check_folder(RCXC_CORPUS_DIR);
}

TEST(FormatPrograms, SemanticTestsKeepTheirImages) { check_folder(fs::path(RCXC_SOURCE_DIR) / "tests" / "semantic"); }

TEST(FormatPrograms, ExamplesKeepTheirImages) { check_folder(fs::path(RCXC_SOURCE_DIR) / "examples"); }

TEST(FormatPrograms, GeneratedProgramsKeepTheirImages) {
  for (unsigned seed = 1; seed <= 40; ++seed) {
    check_program("gen.nqc", test::Generator(seed).program());
    check_program("coin.nqc", test::CoinGenerator(seed).program());
    check_program("two.nqc", test::TwoTaskGenerator(seed).program());
    check_program("expr.nqc", test::ExpressionGenerator(seed).program());
  }
}

// Prose and half statements in branches the preprocessor leaves out, kept
// as written (docs/format.md), around code laid out as usual: the layout
// worked out by hand, and the same image before and after.
TEST(FormatPrograms, BranchesLeftOutKeepTheirTextAndTheImage) {
  const std::string text =
      "int x;\n#if 0\nThis is a note about the motor\n  x = \n#endif\ntask main() {\n"
      "#if 0\n  Wait(1\n#else\n x=2;Wait(2);\n#endif\n#ifdef NOTES\n  See the manual\n#endif\n"
      "#if 1\nOnFwd(OUT_A);\n#else\n  OnRev(OUT_A\n#endif\nx = 1 +\n#if 0\n    2 +\n#endif\n3;\n}\n";
  const std::string want =
      "int x;\n#if 0\nThis is a note about the motor\n  x =\n#endif\ntask main()\n{\n"
      "#if 0\n  Wait(1\n#else\n  x = 2;\n  Wait(2);\n#endif\n#ifdef NOTES\n  See the manual\n#endif\n"
      "#if 1\n  OnFwd(OUT_A);\n#else\n  OnRev(OUT_A\n#endif\n  x = 1 +\n#if 0\n    2 +\n#endif\n      3;\n}\n";
  ASSERT_TRUE(image_of("branches.nqc", text).has_value());
  EXPECT_EQ(formatted(text), want);
  EXPECT_TRUE(check_program("branches.nqc", text));
}

// Random edits of real programs (text that lexes, mostly with syntax
// errors): every result is a lexical refusal or a text that formats to
// itself; the layout never trips the re-lex check.
TEST(FormatPrograms, RandomlyEditedProgramsFormatOrAreRefusedForTheirLexing) {
  std::vector<std::string> seeds;
  for (const auto& f : test::nqc_programs_under(RCXC_SOURCE_DIR "/tests/semantic")) seeds.push_back(test::read_text_file(f));
  ASSERT_FALSE(seeds.empty());
  std::mt19937 rng(7);
  auto below = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  const std::string alphabet = "abX_09 ;{}()[]#/*\"'\n\t=+-<>&|!~?:,$@\\\r";
  const std::vector<std::string> words = {
      "#",      "\\\n",  "\n",    " else ", "if",   " do ",   "case 1", "default", "asm",   "while",      "switch",
      "for",    "repeat", "until",  "monitor", "catch", "/*c*/", "//c\n", "'a'",     "\"s\"", "#define Q 1\n",
      "#if 1\n", "#else\n", "#endif\n", "#if 0\n", "#elif 0\n", "#ifdef A\n", "- -", "++", "x", "1", "return", "&", "int &"};
  int formatted_count = 0;
  for (int round = 0; round < 10000; ++round) {
    std::string text = seeds[below(seeds.size())];
    for (std::size_t e = 0, n = 1 + below(12); e < n; ++e) {
      std::size_t at = below(text.size() + 1);
      if (below(3) == 0 && at < text.size())
        text.erase(at, 1 + below(6));
      else if (below(2) == 0)
        text.insert(at, 1, alphabet[below(alphabet.size())]);
      else
        text.insert(at, words[below(words.size())]);
    }
    auto out = format::format_source(text);
    if (auto* r = std::get_if<format::Refusal>(&out)) {
      EXPECT_EQ(r->message.rfind("cannot format: line ", 0), 0u) << r->message << "\n" << text;
      continue;
    }
    ++formatted_count;
    const std::string& once = std::get<std::string>(out);
    auto twice = format::format_source(once);
    ASSERT_TRUE(std::holds_alternative<std::string>(twice)) << once;
    EXPECT_EQ(std::get<std::string>(twice), once) << "input:\n" << text;
    if (HasFailure()) break;
  }
  EXPECT_GT(formatted_count, 3000);
}

// A large program (the statement tests over and over, to about 700 KB) formats in
// well under the time a compile of it takes.
TEST(FormatPrograms, LargeFileFormatsQuickly) {
  std::string unit;
  for (const auto& f : test::nqc_programs_under(RCXC_SOURCE_DIR "/tests/semantic/statements"))
    unit += test::read_text_file(f) + "\n";
  ASSERT_FALSE(unit.empty());
  std::string big;
  while (big.size() + unit.size() < 700 * 1024) big += unit;  // room for what the layout adds
  std::variant<std::string, format::Refusal> out;
  double ms = 1000 * test::cpu_seconds_for([&] { out = format::format_source(big); });
  ASSERT_TRUE(std::holds_alternative<std::string>(out)) << std::get<format::Refusal>(out).message;
  std::cout << big.size() << " bytes formatted in " << ms << " ms of CPU\n";
  EXPECT_LT(ms, 5000);
}

}  // namespace
}  // namespace rcxc
