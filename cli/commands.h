// Each subcommand of `rcxc` lives in its own file and registers itself here.
// A subcommand's callback stores the process exit code in `exit_code`.
#pragma once

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tomlfile/longest_run.h"

namespace rcxc::cli {

// Exit codes shared by every subcommand (documented in README.md).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  // the input was bad or the run failed
inline constexpr int kExitUsage = 2;    // the command line was bad
inline constexpr int kExitNoPort = 3;   // IR link: the port could not be opened
inline constexpr int kExitNoReply = 4;  // IR link: the brick did not answer / the link failed
inline constexpr int kExitNotComparable = 5;  // compare: nqc is missing or refuses the program

// Whole-number text as typed: an optional sign where one may be typed, then
// digits and nothing else. Its value is told by its digits with the leading
// zeros dropped ("0" for zero), so no conversion can overflow or read octal.
struct WholeNumberText {
  bool negative = false;    // a '-' before digits that are not all zeros
  std::size_t sign = 0;     // 1 when the text starts with '-' or '+'
  std::string_view digits;  // no leading zeros; "0" for zero
};

inline std::optional<WholeNumberText> read_whole_number(std::string_view v, bool sign_allowed) {
  WholeNumberText t;
  t.sign = sign_allowed && (v.starts_with('-') || v.starts_with('+')) ? 1 : 0;
  if (v.size() == t.sign || v.find_first_not_of("0123456789", t.sign) != std::string_view::npos) return std::nullopt;
  t.digits = v.substr(t.sign);
  t.digits.remove_prefix(std::min(t.digits.find_first_not_of('0'), t.digits.size() - 1));
  t.negative = v[0] == '-' && t.digits != "0";
  return t;
}

// Whether `digits` (no leading zeros) is a larger number than `limit` (the same).
inline bool digits_exceed(std::string_view digits, std::string_view limit) {
  return digits.size() != limit.size() ? digits.size() > limit.size() : digits > limit;
}

// CLI11 reads a whole number with a leading zero as octal: `--for 010` ran
// 8 ms and `--seed 010` was seed 8, without a word. Every integer option
// and argument of `app` and its commands is read as decimal (the zeros
// dropped before any check sees the value); 0x stays hexadecimal.
inline void read_integers_as_decimal(CLI::App& app) {
  auto decimal = [](const std::string& v) -> std::string {
    auto number = read_whole_number(v, true);
    // All zeros read the same in octal, and are quoted as typed.
    if (!number || number->digits == "0" || number->sign + number->digits.size() == v.size()) return v;
    return v.substr(0, number->sign).append(number->digits);
  };
  for (CLI::Option* option : app.get_options()) {
    std::string type = option->get_type_name();
    if (type.rfind("INT", 0) == 0 || type.rfind("UINT", 0) == 0) option->transform(decimal);
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) read_integers_as_decimal(*sub);
}

// For options naming a file, port or program: an empty value ("--trace ''",
// a variable that expanded to nothing) would read as the option not given,
// and the command would go on silently without it.
inline CLI::Validator not_empty() {
  return CLI::Validator([](std::string& v) { return v.empty() ? std::string("needs a value, not ''") : std::string(); },
                        "", "not empty");
}

// For unsigned options (seeds): CLI11 would take "-1" as 2^64 - 1, and a
// number past 64 bits as 2^64 - 1 without a word.
inline CLI::Validator whole_number() {
  return CLI::Validator(
      [](std::string& v) {
        constexpr std::string_view kMost = "18446744073709551615";
        auto number = read_whole_number(v, false);
        if (!number) return "'" + v + "' is not a whole number 0 or more";
        if (digits_exceed(number->digits, kMost)) return "'" + v + "' is more than " + std::string(kMost);
        return std::string();
      },
      "", "whole number");
}

// For integer options and arguments: the text must be a whole number from
// `lo` to `hi`, checked as typed. Without it a number past the variable's
// type got CLI11's bare "Could not convert", naming no range. `unit`, when
// given, follows the range ("--for: '10s' is not a whole number (1..N ms)":
// a test's @for takes 10s, --for takes milliseconds).
inline CLI::Validator in_range(long long lo, long long hi, const std::string& unit = "") {
  return CLI::Validator(
      [lo, hi, unit](std::string& v) {
        std::string range = std::to_string(lo) + ".." + std::to_string(hi) + (unit.empty() ? "" : " " + unit);
        auto number = read_whole_number(v, true);
        if (!number) return "'" + v + "' is not a whole number (" + range + ")";
        // Past the largest long long it is past every range (and -2^63 past every lo in use).
        if (digits_exceed(number->digits, std::to_string(std::numeric_limits<long long>::max())))
          return "'" + v + "' is outside " + range;
        long long value = std::stoll(std::string(number->digits));
        if (number->negative ? -value < lo || -value > hi : value < lo || value > hi)
          return "'" + v + "' is outside " + range;
        return std::string();
      },
      "", "whole number");
}

// For options that take any real number from `lo` to `hi` (the ends
// included), as typed: "abc" or "" is no number, "nan" none in a range.
inline CLI::Validator number_in(double lo, double hi, const std::string& range) {
  return CLI::Validator(
      [lo, hi, range](std::string& v) {
        char* end = nullptr;
        double d = v.empty() ? 0 : std::strtod(v.c_str(), &end);
        if (v.empty() || end != v.c_str() + v.size() || std::isnan(d)) return "'" + v + "' is not a number (" + range + ")";
        if (d < lo || d > hi) return "'" + v + "' is outside " + range;
        return std::string();
      },
      "", "number");
}

// An option that may be given many times, one value each time (-I, -D,
// --scenario). CLI11's default lets one occurrence swallow the words after
// it, so `rcxc compile -DFOO prog.nqc` would take prog.nqc as a second
// define and then miss its FILE.
inline CLI::Option* add_repeatable(CLI::App* cmd, const std::string& name, std::vector<std::string>& values,
                                   const std::string& help) {
  return cmd->add_option(name, values, help)->allow_extra_args(false);
}

void register_compile(CLI::App& app, int& exit_code);
void register_run(CLI::App& app, int& exit_code);
void register_disasm(CLI::App& app, int& exit_code);
void register_test(CLI::App& app, int& exit_code);
void register_compare(CLI::App& app, int& exit_code);
void register_brick(CLI::App& app, int& exit_code);
void register_download(CLI::App& app, int& exit_code);
void register_remote(CLI::App& app, int& exit_code);
void register_nxt(CLI::App& app, int& exit_code);
void register_lsp(CLI::App& app, int& exit_code);
void register_debug(CLI::App& app, int& exit_code);
void register_format(CLI::App& app, int& exit_code);
void register_help(CLI::App& app, int& exit_code);  // help [COMMAND], version

// `rcxc nxt --json ...` that the command-line parser refused: a script that
// asked for JSON reads the refusal on stdout as it reads any other failure,
// {"ok": false, "action": ..., "error": ...} (the usage text still goes to
// stderr, the exit is still 2). Prints nothing for any other command line.
void print_nxt_usage_error_json(const CLI::App& app, const std::vector<std::string>& words, const std::string& error);

}  // namespace rcxc::cli
