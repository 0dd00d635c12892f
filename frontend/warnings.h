// The kinds of warning rcxc gives, as one table: each kind's name is what
// `-Wno-NAME` and `-Werror=NAME` take, what text diagnostics show after the
// message ("[-Wunused-variable]", as gcc and clang do), what JSON
// diagnostics carry as "code" and what `rcxc lsp` sends as a diagnostic's
// code. The help text and docs/compiler.md's table list them from here.
#pragma once

#include <array>
#include <bitset>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace rcxc {

enum class WarningKind : std::uint8_t {
  UnusedVariable,
  UnusedValue,
  UnreachableCode,
  UnstartedTask,
  AssignInCondition,
  DivisionByZero,
  Overflow,
  Range,
  Source,
  Uninitialized,
  SharedSubroutine,
  UnconfiguredSensor,
  MacroRedefined,
  MacroDefinition,
  ExtraTokens,
  Pragma,
  WarningDirective,
};

struct WarningKindInfo {
  WarningKind kind;
  std::string_view name;
  std::string_view what;  // one line for help texts and docs
};

inline constexpr std::array<WarningKindInfo, 17> kWarningKinds{{
    {WarningKind::UnusedVariable, "unused-variable", "a local variable nothing uses"},
    {WarningKind::UnusedValue, "unused-value", "an expression statement whose value nothing uses (x == 1;)"},
    {WarningKind::UnreachableCode, "unreachable-code", "statements no path reaches"},
    {WarningKind::UnstartedTask, "unstarted-task", "a task no 'start' names"},
    {WarningKind::AssignInCondition, "assign-in-condition", "'=' where a condition is tested"},
    {WarningKind::DivisionByZero, "division-by-zero", "a constant 0 divides (the firmware leaves the value)"},
    {WarningKind::Overflow, "overflow", "a constant that does not fit in 16 bits, or in the byte it is sent as"},
    {WarningKind::Range, "range", "a constant outside the RCX's range (sensor, timer, output, sound, power...)"},
    {WarningKind::Source, "source", "a source the RCX does not have, or an argument its source does not take"},
    {WarningKind::Uninitialized, "uninitialized", "a variable read before anything is written to it"},
    {WarningKind::SharedSubroutine, "shared-subroutine", "a subroutine two tasks run, keeping values in one slot"},
    {WarningKind::UnconfiguredSensor, "unconfigured-sensor", "a sensor's value read where nothing sets it up"},
    {WarningKind::MacroRedefined, "macro-redefined", "a #define of a name already defined differently"},
    {WarningKind::MacroDefinition, "macro-definition", "a #define with a faulty parameter list"},
    {WarningKind::ExtraTokens, "extra-tokens", "text after a directive that takes none"},
    {WarningKind::Pragma, "pragma", "an unknown or malformed #pragma"},
    {WarningKind::WarningDirective, "warning-directive", "the program's own #warning"},
}};

constexpr std::string_view warning_name(WarningKind kind) {
  return kWarningKinds[static_cast<std::size_t>(kind)].name;
}

std::optional<WarningKind> warning_kind_named(std::string_view name);

// Which warnings are given, and which count as errors: from -w, -Werror,
// -Wno-NAME, -WNAME, -Werror=NAME and -Wno-error=NAME, in the order given.
struct WarningPolicy {
  bool none = false;           // -w
  bool all_as_errors = false;  // -Werror
  std::bitset<kWarningKinds.size()> off;
  std::bitset<kWarningKinds.size()> as_error;
  std::bitset<kWarningKinds.size()> not_as_error;

  bool gives(WarningKind kind) const { return !none && !off[static_cast<std::size_t>(kind)]; }
  bool as_error_for(WarningKind kind) const {
    auto i = static_cast<std::size_t>(kind);
    return as_error[i] || (all_as_errors && !not_as_error[i]);
  }
};

// Applies one -W option's text (after the "-W": "error", "no-unused-variable",
// "error=range", "all"...). Returns why it is not one, or nothing.
std::optional<std::string> apply_warning_option(WarningPolicy& policy, std::string_view option);

// "unused-variable, unused-value, ...": for messages naming what exists.
std::string warning_names_list();

}  // namespace rcxc
