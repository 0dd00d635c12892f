// The warning names and the -W options that take them (frontend/warnings.h).
#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <string>

#include "frontend/diagnostics.h"
#include "frontend/warnings.h"

namespace rcxc {
namespace {

TEST(WarningNames, AreDistinctLowerCaseWordsInTheEnumsOrder) {
  std::set<std::string_view> names;
  for (std::size_t i = 0; i < kWarningKinds.size(); ++i) {
    const auto& k = kWarningKinds[i];
    // warning_name indexes the table by the enum's value.
    EXPECT_EQ(static_cast<std::size_t>(k.kind), i) << k.name;
    EXPECT_TRUE(std::regex_match(std::string(k.name), std::regex("[a-z]+(-[a-z]+)*"))) << k.name;
    EXPECT_TRUE(names.insert(k.name).second) << k.name << " twice";
    EXPECT_EQ(warning_kind_named(k.name), k.kind);
  }
  EXPECT_FALSE(warning_kind_named("error"));
}

TEST(WarningOptions, NoNameTurnsOneOffAndNameTurnsItBackOn) {
  WarningPolicy p;
  EXPECT_TRUE(p.gives(WarningKind::Range));
  EXPECT_FALSE(apply_warning_option(p, "no-range"));
  EXPECT_FALSE(p.gives(WarningKind::Range));
  EXPECT_TRUE(p.gives(WarningKind::Overflow));
  EXPECT_FALSE(apply_warning_option(p, "range"));
  EXPECT_TRUE(p.gives(WarningKind::Range));
  EXPECT_FALSE(apply_warning_option(p, "no-range"));
  EXPECT_FALSE(apply_warning_option(p, "all"));
  EXPECT_TRUE(p.gives(WarningKind::Range));
}

TEST(WarningOptions, ErrorsFollowGccsRules) {
  WarningPolicy p;
  EXPECT_FALSE(apply_warning_option(p, "error=overflow"));
  EXPECT_TRUE(p.as_error_for(WarningKind::Overflow));
  EXPECT_FALSE(p.as_error_for(WarningKind::Range));
  EXPECT_FALSE(apply_warning_option(p, "error"));
  EXPECT_FALSE(apply_warning_option(p, "no-error=range"));
  EXPECT_FALSE(p.as_error_for(WarningKind::Range));  // -Werror does not reach it
  EXPECT_TRUE(p.as_error_for(WarningKind::Pragma));
  EXPECT_FALSE(apply_warning_option(p, "no-error"));
  EXPECT_FALSE(p.as_error_for(WarningKind::Pragma));
  EXPECT_TRUE(p.as_error_for(WarningKind::Overflow));  // named on its own
}

TEST(WarningOptions, AnUnknownNameIsRefusedWithTheNearestOrTheList) {
  WarningPolicy p;
  auto near = apply_warning_option(p, "no-unused-varable");
  ASSERT_TRUE(near);
  EXPECT_EQ(*near, "unknown warning option '-Wno-unused-varable'; did you mean 'unused-variable'?");
  auto far = apply_warning_option(p, "shadow");
  ASSERT_TRUE(far);
  EXPECT_NE(far->find("unknown warning option '-Wshadow' (the warnings are: unused-variable, unused-value,"),
            std::string::npos)
      << *far;
  EXPECT_TRUE(apply_warning_option(p, "error=nothing"));
  EXPECT_TRUE(apply_warning_option(p, ""));
  WarningPolicy fresh;
  EXPECT_EQ(p.off, fresh.off);  // refused options changed nothing
  EXPECT_EQ(p.as_error, fresh.as_error);
}

TEST(WarningOptions, TextAndJsonNameTheWarning) {
  SourceManager sm;
  auto f = sm.add("a.nqc", "int x;\n");
  Diagnostics diags;
  diags.policy.as_error[static_cast<std::size_t>(WarningKind::Overflow)] = true;
  diags.warning({{f, 1, 5}, {f, 1, 6}}, WarningKind::UnusedVariable, "unused variable 'x'");
  diags.warning({{f, 1, 5}, {f, 1, 6}}, WarningKind::Overflow, "too big");
  diags.error({{f, 1, 1}, {f, 1, 2}}, "plain");
  const auto& all = diags.all();
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(render_text(all[0], sm).substr(0, 55), "a.nqc:1:5: warning: unused variable 'x' [-Wunused-varia");
  EXPECT_NE(render_text(all[1], sm).find("a.nqc:1:5: error: too big [-Werror=overflow]\n"), std::string::npos);
  EXPECT_NE(render_text(all[2], sm).find("error: plain\n"), std::string::npos);
  EXPECT_NE(render_json(all[0], sm).find("\"code\":\"unused-variable\""), std::string::npos);
  EXPECT_NE(render_json(all[1], sm).find("\"code\":\"overflow\""), std::string::npos);
  EXPECT_EQ(render_json(all[2], sm).find("\"code\""), std::string::npos);
}

}  // namespace
}  // namespace rcxc
