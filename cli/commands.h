// Each subcommand of `rcxc` lives in its own file and registers itself here.
// A subcommand's callback stores the process exit code in `exit_code`.
#pragma once

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rcxc::cli {

// Exit codes shared by every subcommand (documented in README.md).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  // the input was bad or the run failed
inline constexpr int kExitUsage = 2;    // the command line was bad
inline constexpr int kExitNoPort = 3;   // IR link: the port could not be opened
inline constexpr int kExitNoReply = 4;  // IR link: the brick did not answer / the link failed
inline constexpr int kExitNotComparable = 5;  // compare: nqc is missing or refuses the program

// The longest virtual run --for accepts (about 35 years): milliseconds times
// 1000 must still fit the emulator's 64-bit microsecond clock.
inline constexpr std::int64_t kMaxRunMs = std::int64_t{1} << 40;

// CLI11 reads a whole number with a leading zero as octal: `--for 010` ran
// 8 ms and `--seed 010` was seed 8, without a word. Every integer option
// and argument of `app` and its commands is read as decimal (the zeros
// dropped before any check sees the value); 0x stays hexadecimal.
inline void read_integers_as_decimal(CLI::App& app) {
  auto decimal = [](const std::string& v) -> std::string {
    std::size_t sign = v.starts_with('-') || v.starts_with('+') ? 1 : 0;
    bool digits = v.size() > sign && v.find_first_not_of("0123456789", sign) == std::string::npos;
    std::size_t first = v.find_first_not_of('0', sign);  // npos: all zeros, which octal reads right
    if (!digits || first == std::string::npos || first == sign) return v;
    return v.substr(0, sign).append(v, first);
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

// For unsigned options (seeds): CLI11 would take "-1" as 2^64 - 1.
inline CLI::Validator whole_number() {
  return CLI::Validator(
      [](std::string& v) {
        bool digits = !v.empty() && v.find_first_not_of("0123456789") == std::string::npos;
        if (!digits) return "'" + v + "' is not a whole number 0 or more";
        // Past 64 bits the conversion gives 2^64 - 1 without a word.
        constexpr std::string_view kMost = "18446744073709551615";
        std::string_view n = std::string_view(v).substr(std::min(v.find_first_not_of('0'), v.size() - 1));
        if (n.size() > kMost.size() || (n.size() == kMost.size() && n > kMost))
          return "'" + v + "' is more than " + std::string(kMost);
        return std::string();
      },
      "", "whole number");
}

// For integer options and arguments: the text must be a whole number from
// `lo` to `hi`, checked as typed. Without it a number past the variable's
// type got CLI11's bare "Could not convert", naming no range.
inline CLI::Validator in_range(long long lo, long long hi) {
  return CLI::Validator(
      [lo, hi](std::string& v) {
        std::string range = std::to_string(lo) + ".." + std::to_string(hi);
        std::size_t sign = v.starts_with('-') || v.starts_with('+') ? 1 : 0;
        bool digits = v.size() > sign && v.find_first_not_of("0123456789", sign) == std::string::npos;
        if (!digits) return "'" + v + "' is not a whole number (" + range + ")";
        // Leading zeros and a sign cannot make the digits' count lie about size.
        std::string_view n = std::string_view(v).substr(sign);
        n.remove_prefix(std::min(n.find_first_not_of('0'), n.size() - 1));
        bool negative = v[0] == '-' && n != "0";
        bool beyond = n.size() > 18;  // 19 digits may not fit a long long
        long long value = beyond ? 0 : std::stoll(std::string(n));
        if (beyond || (negative ? -value < lo : value > hi) || (negative ? -value > hi : value < lo))
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
void register_format(CLI::App& app, int& exit_code);
void register_help(CLI::App& app, int& exit_code);  // help [COMMAND], version

}  // namespace rcxc::cli
