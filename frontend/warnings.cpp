#include "frontend/warnings.h"

#include <vector>

#include "frontend/spelling.h"

namespace rcxc {

std::optional<WarningKind> warning_kind_named(std::string_view name) {
  for (const auto& k : kWarningKinds)
    if (k.name == name) return k.kind;
  return std::nullopt;
}

std::string warning_names_list() {
  std::string out;
  for (const auto& k : kWarningKinds) out += (out.empty() ? "" : ", ") + std::string(k.name);
  return out;
}

namespace {

std::string unknown_name(std::string_view option, std::string_view name) {
  std::vector<std::string> names;
  for (const auto& k : kWarningKinds) names.emplace_back(k.name);
  std::string why = "unknown warning option '-W" + std::string(option) + "'";
  if (auto near = frontend::closest_name(name, names)) return why + "; did you mean '" + *near + "'?";
  return why + " (the warnings are: " + warning_names_list() + ")";
}

}  // namespace

std::optional<std::string> apply_warning_option(WarningPolicy& policy, std::string_view option) {
  // gcc's habits: -Wall and -Wextra ask for what rcxc gives anyway.
  if (option == "all" || option == "extra") {
    policy.none = false;
    policy.off.reset();
    return std::nullopt;
  }
  if (option == "error") {
    policy.all_as_errors = true;
    return std::nullopt;
  }
  if (option == "no-error") {
    policy.all_as_errors = false;
    return std::nullopt;
  }
  struct Form {
    std::string_view prefix;
    void (*apply)(WarningPolicy&, std::size_t);
  };
  static constexpr Form forms[] = {
      {"no-error=", [](WarningPolicy& p, std::size_t i) { p.as_error[i] = false, p.not_as_error[i] = true; }},
      {"error=",
       [](WarningPolicy& p, std::size_t i) { p.as_error[i] = true, p.not_as_error[i] = false, p.off[i] = false; }},
      {"no-", [](WarningPolicy& p, std::size_t i) { p.off[i] = true; }},
      {"", [](WarningPolicy& p, std::size_t i) { p.off[i] = false; }},
  };
  for (const auto& form : forms) {
    if (!option.starts_with(form.prefix)) continue;
    std::string_view name = option.substr(form.prefix.size());
    auto kind = warning_kind_named(name);
    if (!kind) return unknown_name(option, name);
    form.apply(policy, static_cast<std::size_t>(*kind));
    return std::nullopt;
  }
  return unknown_name(option, option);
}

}  // namespace rcxc
