#include "verify/testspec.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "rcx/file_read.h"
#include "rcx/printable_text.h"
#include "runtime/scenario.h"
#include "tomlfile/longest_run.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

namespace rcx::semtest {
namespace {

// ------------------------------------------------------------ tokens

std::vector<std::string> tokenize(std::string_view text) {
  std::vector<std::string> out;
  std::string cur;
  auto flush = [&] {
    if (!cur.empty()) out.push_back(std::move(cur));
    cur.clear();
  };
  for (char c : text) {
    if (c == ' ' || c == '\t' || c == '\r') {
      flush();
    } else if (c == ':' || c == ',') {
      flush();
      out.emplace_back(1, c);
    } else {
      cur += c;
    }
  }
  flush();
  // `at 1s±50ms` / `at 1s +-50ms`: split the tolerance off as its own token.
  std::vector<std::string> split;
  for (auto& t : out) {
    for (std::string_view pm : {"\xC2\xB1", "+-"}) {
      auto at = t.find(pm);
      if (at != std::string::npos && at > 0) {
        split.push_back(t.substr(0, at));
        t = t.substr(at);
        break;
      }
    }
    split.push_back(std::move(t));
  }
  return split;
}

class Cursor {
 public:
  explicit Cursor(std::vector<std::string> toks) : toks_(std::move(toks)) {}
  bool done() const { return pos_ >= toks_.size(); }
  const std::string& peek() const {
    static const std::string empty;
    return done() ? empty : toks_[pos_];
  }
  std::string next() { return done() ? std::string() : toks_[pos_++]; }
  bool accept(std::string_view word) {
    if (!done() && toks_[pos_] == word) {
      ++pos_;
      return true;
    }
    return false;
  }
  std::string rest() const {
    std::string s;
    for (std::size_t i = pos_; i < toks_.size(); ++i) s += (s.empty() ? "" : " ") + toks_[i];
    return s;
  }

 private:
  std::vector<std::string> toks_;
  std::size_t pos_ = 0;
};

struct ParseFail {
  std::string message;
};

std::optional<int> to_int(std::string_view s) {
  int v = 0;
  bool neg = !s.empty() && s[0] == '-';
  std::string_view digits = neg ? s.substr(1) : s;
  int base = 10;
  if (digits.size() > 2 && digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X')) {
    digits.remove_prefix(2);
    base = 16;
  }
  // One sign at most: from_chars takes its own '-', so "--5" and "-0x-5"
  // would read as 5.
  if (neg && !digits.empty() && digits[0] == '-') return std::nullopt;
  auto [p, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v, base);
  if (ec != std::errc() || p != digits.data() + digits.size() || digits.empty() || (base == 16 && v < 0))
    return std::nullopt;
  return neg ? -v : v;
}

// Digits with at most one sign and a 0x, as to_int reads them, however many:
// a number, though perhaps too large for any directive.
bool whole_number_text(std::string_view s) {
  if (!s.empty() && s[0] == '-') s.remove_prefix(1);
  bool hex = s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X');
  if (hex) s.remove_prefix(2);
  return !s.empty() && std::all_of(s.begin(), s.end(), [&](char d) {
    return hex ? std::isxdigit(static_cast<unsigned char>(d)) != 0 : std::isdigit(static_cast<unsigned char>(d)) != 0;
  });
}

// A number too large for the range is named as such, not as no number.
int need_range(Cursor& c, std::string_view what, int lo, int hi) {
  std::string t = c.next();
  auto v = to_int(t);
  if (!v && whole_number_text(t)) throw ParseFail{fmt::format("{} {} is out of range {}..{}", what, t, lo, hi)};
  if (!v) throw ParseFail{fmt::format("expected {} (a number), found '{}'", what, t)};
  if (*v < lo || *v > hi) throw ParseFail{fmt::format("{} {} is out of range {}..{}", what, *v, lo, hi)};
  return *v;
}

int need_int(Cursor& c, std::string_view what) {
  return need_range(c, what, std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
}

// "500ms", "1.5s", "2s", "750" (milliseconds).
Micros need_time(Cursor& c, std::string_view what) {
  std::string t = c.next();
  std::string_view s = t;
  double scale = 1000.0;  // micros per unit; default unit ms
  if (s.size() > 2 && s.substr(s.size() - 2) == "ms") {
    s.remove_suffix(2);
  } else if (s.size() > 1 && s.back() == 's') {
    s.remove_suffix(1);
    scale = 1'000'000.0;
  }
  double v = 0;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  // from_chars reads "nan" and "inf" too; NaN passes every comparison.
  if (ec == std::errc() && p == s.data() + s.size() && !std::isfinite(v))
    throw ParseFail{fmt::format("expected {} (like 500ms or 2s), found '{}', which is not a finite number", what, t)};
  bool number = ec == std::errc() && p == s.data() + s.size() && !s.empty();
  if (number && v < 0)
    throw ParseFail{fmt::format("expected {} (like 500ms or 2s), found '{}', which is negative", what, t)};
  // from_chars says out of range for a number past a double's (or so small
  // it is 0: "1e-400").
  bool too_large = ec == std::errc::result_out_of_range && p == s.data() + s.size() && s.front() != '-' &&
                   s.find("e-") == std::string_view::npos && s.find("E-") == std::string_view::npos;
  if (too_large || (number && v * scale > static_cast<double>(rcxc::kLongestRunMs * kMicrosPerMs)))
    throw ParseFail{fmt::format("expected {} (like 500ms or 2s), found '{}', which is later than the longest run ({} "
                                "ms, about 35 years)",
                                what, t, rcxc::kLongestRunMs)};
  if (!number) throw ParseFail{fmt::format("expected {} (like 500ms or 2s), found '{}'", what, t)};
  return static_cast<Micros>(std::llround(v * scale));
}

void need(Cursor& c, std::string_view word) {
  if (!c.accept(word)) throw ParseFail{fmt::format("expected '{}', found '{}'", word, c.peek())};
}

void need_end(Cursor& c) {
  if (!c.done()) throw ParseFail{fmt::format("unexpected '{}'", c.rest())};
}

Cmp need_cmp(Cursor& c) {
  std::string t = c.next();
  if (t == "==") return Cmp::Eq;
  if (t == "!=") return Cmp::Ne;
  if (t == "<") return Cmp::Lt;
  if (t == "<=") return Cmp::Le;
  if (t == ">") return Cmp::Gt;
  if (t == ">=") return Cmp::Ge;
  throw ParseFail{fmt::format("expected a comparison (== != < <= > >=), found '{}'", t)};
}

int need_output(Cursor& c) {
  std::string t = c.next();
  if (t == "A" || t == "a") return 0;
  if (t == "B" || t == "b") return 1;
  if (t == "C" || t == "c") return 2;
  throw ParseFail{fmt::format("expected an output A, B or C, found '{}'", t)};
}

// Optional "on|off|float", "fwd|rev", power digits, in any order.
void output_fields(Cursor& c, std::optional<OutputMode>& mode, std::optional<Direction>& dir,
                   std::optional<int>& power) {
  while (!c.done()) {
    const std::string& t = c.peek();
    if (t == "on") mode = OutputMode::On;
    else if (t == "off") mode = OutputMode::Off;
    else if (t == "float") mode = OutputMode::Float;
    else if (t == "fwd") dir = Direction::Forward;
    else if (t == "rev") dir = Direction::Reverse;
    else if (auto p = to_int(t); p && *p >= 0 && *p <= 7) power = *p;
    else break;
    c.next();
  }
}

EventPattern need_event(Cursor& c) {
  EventPattern p;
  std::string kind = c.next();
  if (kind == "sound") {
    p.kind = EventKind::Sound;
    if (!c.done() && whole_number_text(c.peek())) p.value = need_range(c, "sound", 0, 5);
  } else if (kind == "tone") {
    p.kind = EventKind::Tone;
    if (!c.done() && whole_number_text(c.peek())) p.value = need_int(c, "frequency");
    if (!c.done() && whole_number_text(c.peek())) p.duration = need_int(c, "duration");
  } else if (kind == "output") {
    p.kind = EventKind::Output;
    p.index = need_output(c);
    output_fields(c, p.mode, p.dir, p.power);
  } else if (kind == "display") {
    p.kind = EventKind::Display;
    if (!c.done() && whole_number_text(c.peek())) p.value = need_range(c, "display", 0, 6);
  } else if (kind == "send") {
    p.kind = EventKind::MessageSent;
    if (!c.done() && whole_number_text(c.peek())) p.value = need_range(c, "message", 0, 255);
  } else if (kind == "receive") {
    // A message that arrived: from the test's inputs or another @brick.
    p.kind = EventKind::MessageReceived;
    if (!c.done() && whole_number_text(c.peek())) p.value = need_range(c, "message", 0, 255);
  } else if (kind == "datalog") {
    p.kind = EventKind::Datalog;
    if (!c.done() && whole_number_text(c.peek())) p.value = need_int(c, "datalog value");
  } else if (kind == "task-start" || kind == "task-stop") {
    p.kind = kind == "task-start" ? EventKind::TaskStart : EventKind::TaskStop;
    std::string t = c.next();
    if (t.empty()) throw ParseFail{"expected a task name or number"};
    if (auto n = to_int(t)) p.index = *n;
    else p.task_name = t;
  } else {
    throw ParseFail{fmt::format(
        "unknown event '{}' (sound, tone, output, display, send, receive, datalog, task-start, task-stop)", kind)};
  }
  return p;
}

Input need_input(Cursor& c) {
  std::string kind = c.next();
  if (kind == "sensor") {
    int sensor = need_range(c, "sensor", 1, 3) - 1;
    std::string what = c.next();
    if (what == "raw") return SensorRawInput{sensor, need_range(c, "raw value", 0, 1023)};
    if (what == "rotation") return RotationInput{sensor, need_range(c, "rotation", -32768, 32767)};
    // A touch sensor reads a low raw value when pressed, high when released.
    if (what == "pressed") return SensorRawInput{sensor, 100};
    if (what == "released") return SensorRawInput{sensor, 1023};
    throw ParseFail{fmt::format("expected raw N, rotation N, pressed or released after the sensor, found '{}'", what)};
  }
  if (kind == "message") return MessageInput{need_range(c, "message", 0, 255)};
  if (kind == "battery") return BatteryInput{need_range(c, "battery millivolts", 0, 12000)};
  throw ParseFail{fmt::format("unknown input '{}' (sensor, message, battery)", kind)};
}

StopKind need_stop(Cursor& c) {
  std::string t = c.next();
  if (t == "ended") return StopKind::Ended;
  if (t == "time_limit") return StopKind::TimeLimit;
  if (t == "power_off") return StopKind::PowerOff;
  if (t == "fault") return StopKind::Fault;
  throw ParseFail{fmt::format("expected ended, time_limit, power_off or fault, found '{}'", t)};
}

Check need_expect(Cursor& c) {
  std::string what = c.next();
  if (what == "stop") return ExpectStop{need_stop(c)};
  if (what == "global") {
    std::string name = c.next();
    if (name.empty()) throw ParseFail{"expected a global variable name"};
    Cmp cmp = need_cmp(c);
    return ExpectGlobal{name, cmp, need_int(c, "value")};
  }
  if (what == "var") {
    int index = need_range(c, "variable", 0, kMaxVariables - 1);
    Cmp cmp = need_cmp(c);
    return ExpectVar{index, cmp, need_int(c, "value")};
  }
  if (what == "output") {
    ExpectOutput o{need_output(c), {}, {}, {}};
    c.accept(":");
    output_fields(c, o.mode, o.dir, o.power);
    if (!o.mode && !o.dir && !o.power) throw ParseFail{"expected on/off/float, fwd/rev or a power 0..7"};
    return o;
  }
  if (what == "message") {
    Cmp cmp = need_cmp(c);
    return ExpectMessage{cmp, need_int(c, "value")};
  }
  if (what == "display") {
    Cmp cmp = need_cmp(c);
    return ExpectDisplay{cmp, need_int(c, "value")};
  }
  if (what == "datalog") {
    c.accept(":");
    ExpectDatalog d;
    while (!c.done()) {
      if (c.accept(",")) continue;
      d.values.push_back(need_int(c, "datalog value"));
    }
    return d;
  }
  if (what == "event" || what == "no") {
    ExpectEvent e;
    if (what == "no") {
      need(c, "event");
      e.absent = true;
    }
    if (c.accept("at")) {
      e.at_us = need_time(c, "event time");
      std::string tol = c.peek();
      if (tol.rfind("+-", 0) == 0 || tol.rfind("\xC2\xB1", 0) == 0) {
        c.next();
        Cursor t({tol.substr(2)});  // "+-" and "±" are both two bytes
        e.tolerance_us = need_time(t, "tolerance");
      }
    }
    c.accept(":");
    e.pattern = need_event(c);
    return e;
  }
  if (what == "count") {
    ExpectCount n;
    n.pattern = need_event(c);
    n.cmp = need_cmp(c);
    n.value = need_int(c, "count");
    return n;
  }
  throw ParseFail{fmt::format(
      "unknown expectation '{}' (stop, global, var, output, message, display, datalog, event, no event, count)", what)};
}

// The text after "@" on a comment line, or nullopt when there is none.
std::optional<std::string_view> directive_of(std::string_view line) {
  auto c = line.find("//");
  if (c == std::string_view::npos) return std::nullopt;
  std::string_view rest = line.substr(c + 2);
  auto first = rest.find_first_not_of(" \t");
  if (first == std::string_view::npos || rest[first] != '@') return std::nullopt;
  return rest.substr(first + 1);
}

void parse_directive(std::string_view text, int line, Spec& spec) {
  auto space = text.find_first_of(" \t:");
  std::string_view word = text.substr(0, space);
  Cursor c(tokenize(space == std::string_view::npos ? std::string_view() : text.substr(space)));
  // A directive that sets one value, given twice: the later one won
  // without a word, so the run was not the one the first line said.
  auto once = [&](int& first_line) {
    if (first_line) throw ParseFail{fmt::format("a second @{} (the first is on line {})", word, first_line)};
    first_line = line;
  };
  if (word == "for") {
    once(spec.for_line);
    spec.run_for_us = need_time(c, "run length");
    // As `rcxc run --for 0`: a run of no time checks nothing but the start.
    if (*spec.run_for_us == 0) throw ParseFail{"the run length must be more than 0 ms"};
    need_end(c);
  } else if (word == "seed") {
    once(spec.seed_line);
    int seed = need_range(c, "seed", 0, std::numeric_limits<int>::max());
    spec.seed = static_cast<std::uint64_t>(seed);
    need_end(c);
  } else if (word == "scenario") {
    once(spec.scenario_line);
    c.accept(":");
    spec.scenario_file = c.next();
    if (spec.scenario_file.empty()) throw ParseFail{"expected a scenario file name"};
    need_end(c);
  } else if (word == "brick") {
    if (spec.bricks.size() == kMostOtherBricks)
      throw ParseFail{fmt::format("an @brick more than {}: a room holds 8 bricks, this test's and {} others",
                                  kMostOtherBricks, kMostOtherBricks)};
    c.accept(":");
    std::string file = c.next();
    if (file.empty()) throw ParseFail{"expected the file of the other brick's program, e.g. @brick slave.nqc"};
    need_end(c);
    spec.bricks.push_back({line, std::move(file)});
  } else if (word == "options") {
    // Words split at blanks only: an option's value may hold ':' or ','.
    once(spec.options_line);
    std::istringstream words(std::string(space == std::string_view::npos ? std::string_view() : text.substr(space)));
    for (std::string w; words >> w;)
      if (!(spec.options.empty() && w == ":")) spec.options.push_back(w);
    if (spec.options.empty()) throw ParseFail{"expected compiler options, e.g. @options -O0 -DSPEED=5"};
  } else if (word == "nqc-differs") {
    // A note for the comparison runs: nqc's code for this program is known to
    // behave differently (the reason follows); `rcxc test --nqc` skips it.
    spec.nqc_differs = true;
  } else if (word == "input") {
    need(c, "at");
    Micros at = need_time(c, "input time");
    c.accept(":");
    spec.inputs.push_back({at, need_input(c)});
    need_end(c);
  } else if (word == "expect") {
    // A bare `@expect` (nothing after the word) has no text to keep.
    std::string_view what = space == std::string_view::npos ? std::string_view() : text.substr(space);
    what.remove_prefix(std::min(what.find_first_not_of(" \t"), what.size()));
    Expectation e{line, std::string(what), need_expect(c)};
    need_end(c);
    spec.expectations.push_back(std::move(e));
  } else if (word == "expect-error" || word == "expect-warning") {
    // Raw text, not tokens: the message is matched as written.
    ExpectDiagnostic d{line, word == "expect-error", std::nullopt, {}};
    std::string_view rest = space == std::string_view::npos ? std::string_view() : text.substr(space);
    auto trim = [](std::string_view v) {
      auto b = v.find_first_not_of(" \t");
      auto e = v.find_last_not_of(" \t\r");
      return b == std::string_view::npos ? std::string_view() : v.substr(b, e - b + 1);
    };
    rest = trim(rest);
    if (rest.rfind("line", 0) == 0) {
      Cursor n(tokenize(rest.substr(4)));
      // Lines count from 1: `line 0` or `line -1` was an expectation no
      // diagnostic could meet, told only as "the compiler said: nothing".
      d.at_line = need_range(n, "line number", 1, std::numeric_limits<int>::max());
      auto colon = rest.find(':');
      rest = colon == std::string_view::npos ? std::string_view() : rest.substr(colon + 1);
    } else if (!rest.empty() && rest[0] == ':') {
      rest.remove_prefix(1);
    }
    d.text = std::string(trim(rest));
    spec.diagnostics.push_back(std::move(d));
  } else {
    throw ParseFail{fmt::format(
        "unknown directive '@{}' (for, seed, scenario, options, input, brick, expect, expect-error, expect-warning, "
        "nqc-differs)", word)};
  }
}

// ------------------------------------------------------------ checking

bool compare(int actual, Cmp cmp, int expected) {
  switch (cmp) {
    case Cmp::Eq: return actual == expected;
    case Cmp::Ne: return actual != expected;
    case Cmp::Lt: return actual < expected;
    case Cmp::Le: return actual <= expected;
    case Cmp::Gt: return actual > expected;
    case Cmp::Ge: return actual >= expected;
  }
  return false;
}

std::string output_text(const Output& o) {
  return fmt::format("{} {} {}", to_string(o.mode), o.dir == Direction::Forward ? "fwd" : "rev", o.power);
}

std::string event_text(const Event& e, const Image& image) {
  std::string t = fmt::format("{}ms ", e.t_us / kMicrosPerMs);
  switch (e.kind) {
    case EventKind::Output: return t + fmt::format("output {} {}", "ABC"[e.index % 3], output_text(e.output));
    case EventKind::Sound: return t + fmt::format("sound {}", e.value);
    case EventKind::Tone: return t + fmt::format("tone {} {}", e.value, e.duration);
    case EventKind::Display: return t + fmt::format("display {}", e.value);
    case EventKind::MessageSent: return t + fmt::format("send {}", e.value);
    case EventKind::Datalog: return t + fmt::format("datalog {}", e.value);
    case EventKind::TaskStart:
    case EventKind::TaskStop: {
      std::string name = image.name_of(SymbolType::Task, e.index);
      return t + fmt::format("{} {}", e.kind == EventKind::TaskStart ? "task-start" : "task-stop",
                             name.empty() ? std::to_string(e.index) : name);
    }
    case EventKind::Sensor: return t + fmt::format("sensor {} = {}", e.index + 1, e.value);
    case EventKind::Variable: return t + fmt::format("var {} = {}", e.index, e.value);
    case EventKind::SensorReading: return t + fmt::format("SENSOR_{} reads {}", e.index + 1, e.value);
    case EventKind::MessageReceived: return t + fmt::format("receive {}", e.value);
  }
  return t;
}

bool matches(const EventPattern& p, const Event& e, const Image& image) {
  if (e.kind != p.kind) return false;
  if (p.index && e.index != *p.index) return false;
  if (!p.task_name.empty() && image.name_of(SymbolType::Task, e.index) != p.task_name) return false;
  if (p.value && e.value != *p.value) return false;
  if (p.duration && e.duration != *p.duration) return false;
  if (p.mode && e.output.mode != *p.mode) return false;
  if (p.dir && e.output.dir != *p.dir) return false;
  if (p.power && e.output.power != *p.power) return false;
  return true;
}

// The events of the pattern's kind, for "what happened instead" messages.
std::string events_of_kind(const Machine& m, const Image& image, EventKind kind) {
  std::string s;
  int shown = 0, total = 0;
  for (const auto& e : m.state().events) {
    if (e.kind != kind) continue;
    ++total;
    if (shown < 12) {
      s += "\n      " + event_text(e, image);
      ++shown;
    }
  }
  if (total == 0) return " (no such events happened)";
  if (total > shown) s += fmt::format("\n      ... {} more", total - shown);
  return "; these happened:" + s;
}

std::optional<std::string> check_one(const Check& check, const Machine& m, const Image& image) {
  const State& s = m.state();
  if (auto* c = std::get_if<ExpectStop>(&check)) {
    if (m.stop().kind == c->kind) return std::nullopt;
    return fmt::format("the run stopped with '{}'", to_string(m.stop().kind));
  }
  if (auto* c = std::get_if<ExpectGlobal>(&check)) {
    for (const auto& sym : image.symbols) {
      if (sym.type != SymbolType::Variable || sym.name != c->name) continue;
      int v = s.vars[sym.index];
      if (compare(v, c->cmp, c->value)) return std::nullopt;
      return fmt::format("got {} = {}", c->name, v);
    }
    return fmt::format("the program has no global variable '{}'", c->name);
  }
  if (auto* c = std::get_if<ExpectVar>(&check)) {
    int v = s.vars[static_cast<std::size_t>(c->index)];
    if (compare(v, c->cmp, c->value)) return std::nullopt;
    return fmt::format("got var {} = {}", c->index, v);
  }
  if (auto* c = std::get_if<ExpectOutput>(&check)) {
    const Output& o = s.outputs[static_cast<std::size_t>(c->index)];
    if ((!c->mode || o.mode == *c->mode) && (!c->dir || o.dir == *c->dir) && (!c->power || o.power == *c->power))
      return std::nullopt;
    return fmt::format("output {} is {}", "ABC"[c->index], output_text(o));
  }
  if (auto* c = std::get_if<ExpectMessage>(&check)) {
    if (compare(s.message, c->cmp, c->value)) return std::nullopt;
    return fmt::format("the message buffer holds {}", s.message);
  }
  if (auto* c = std::get_if<ExpectDisplay>(&check)) {
    if (compare(s.display, c->cmp, c->value)) return std::nullopt;
    return fmt::format("the display shows {}", s.display);
  }
  if (auto* c = std::get_if<ExpectDatalog>(&check)) {
    std::vector<int> got;
    for (const auto& e : s.datalog) got.push_back(e.value);
    if (got == c->values) return std::nullopt;
    return fmt::format("the datalog holds [{}]", fmt::join(got, ", "));
  }
  if (auto* c = std::get_if<ExpectEvent>(&check)) {
    bool found = std::any_of(s.events.begin(), s.events.end(), [&](const Event& e) {
      if (!matches(c->pattern, e, image)) return false;
      return !c->at_us || std::llabs(e.t_us - *c->at_us) <= c->tolerance_us;
    });
    if (found != c->absent) return std::nullopt;
    return std::string(c->absent ? "it happened" : "no matching event") + events_of_kind(m, image, c->pattern.kind);
  }
  if (auto* c = std::get_if<ExpectCount>(&check)) {
    int n = static_cast<int>(std::count_if(s.events.begin(), s.events.end(),
                                           [&](const Event& e) { return matches(c->pattern, e, image); }));
    if (compare(n, c->cmp, c->value)) return std::nullopt;
    return fmt::format("counted {}", n) + events_of_kind(m, image, c->pattern.kind);
  }
  return std::nullopt;
}

}  // namespace

std::string brick_path(const OtherBrick& brick, const std::string& test_path) {
  return (std::filesystem::path(test_path).parent_path() / brick.file).string();
}

std::string scenario_path(const Spec& spec, const std::string& test_path) {
  if (spec.scenario_file.empty()) return "";
  return (std::filesystem::path(test_path).parent_path() / spec.scenario_file).string();
}

std::variant<std::vector<TimedInput>, std::string> all_inputs(const Spec& spec, const std::string& test_path) {
  std::vector<TimedInput> inputs = spec.inputs;
  if (spec.scenario_file.empty()) return inputs;
  auto scenario = read_scenario_file(scenario_path(spec, test_path));
  if (auto* e = std::get_if<ScenarioError>(&scenario)) return e->message;
  auto& more = std::get<std::vector<TimedInput>>(scenario);
  inputs.insert(inputs.end(), more.begin(), more.end());
  return inputs;
}

bool Spec::expects_compile_error() const {
  return std::any_of(diagnostics.begin(), diagnostics.end(), [](const ExpectDiagnostic& d) { return d.error; });
}

bool Spec::expects_task_events() const {
  auto about_tasks = [](const EventPattern& p) { return p.kind == EventKind::TaskStart || p.kind == EventKind::TaskStop; };
  return std::any_of(expectations.begin(), expectations.end(), [&](const Expectation& e) {
    if (const auto* event = std::get_if<ExpectEvent>(&e.check)) return about_tasks(event->pattern);
    if (const auto* count = std::get_if<ExpectCount>(&e.check)) return about_tasks(count->pattern);
    return false;
  });
}

std::variant<Spec, std::vector<SpecError>> parse_spec(std::string_view source) {
  Spec spec;
  std::vector<SpecError> errors;
  int line = 0;
  std::size_t pos = 0;
  while (pos <= source.size()) {
    std::size_t end = source.find('\n', pos);
    if (end == std::string_view::npos) end = source.size();
    ++line;
    if (auto d = directive_of(source.substr(pos, end - pos))) {
      try {
        parse_directive(*d, line, spec);
      } catch (const ParseFail& f) {
        // The message quotes the file's text: its control bytes (an escape
        // sequence, a NUL) are shown, not sent to the terminal.
        errors.push_back({line, printable_text(f.message)});
      }
    }
    pos = end + 1;
  }
  if (!errors.empty()) return errors;
  std::stable_sort(spec.inputs.begin(), spec.inputs.end(),
                   [](const TimedInput& a, const TimedInput& b) { return a.at_us < b.at_us; });
  return spec;
}

std::variant<Spec, std::vector<SpecError>> parse_spec_file(const std::string& path) {
  auto file = read_file(path, kSourceFile);
  // Line 0, about the whole file; the caller names the file.
  if (const auto* problem = std::get_if<FileProblem>(&file)) {
    std::string why = *problem == FileProblem::TooLarge    ? too_large_reason(kSourceFile)
                      : *problem == FileProblem::Directory ? "is a directory, not a file"
                      : *problem == FileProblem::CannotOpen ? "cannot open it: " + cannot_open_reason(path)
                                                            : std::string("cannot read it");
    return std::vector<SpecError>{{0, why}};
  }
  return parse_spec(std::get<std::string>(file));
}

std::vector<Failure> check_diagnostics(const Spec& spec, const std::vector<CompilerMessage>& messages) {
  std::vector<Failure> failures;
  for (const auto& d : spec.diagnostics) {
    bool found = std::any_of(messages.begin(), messages.end(), [&](const CompilerMessage& m) {
      return m.error == d.error && (!d.at_line || m.line == *d.at_line) &&
             m.message.find(d.text) != std::string::npos;
    });
    if (found) continue;
    std::string got;
    for (const auto& m : messages)
      got += fmt::format("\n      line {}: {}: {}", m.line, m.error ? "error" : "warning", printable_text(m.message));
    failures.push_back({d.line, fmt::format("expected {} {}'{}'; the compiler said:{}", d.error ? "error" : "warning",
                                            d.at_line ? fmt::format("at line {} ", *d.at_line) : "",
                                            printable_text(d.text),
                                            got.empty() ? " nothing" : got)});
  }
  if (!spec.expects_compile_error()) {
    for (const auto& m : messages)
      if (m.error) failures.push_back({m.line, fmt::format("unexpected compile error: {}", printable_text(m.message))});
  }
  return failures;
}

std::vector<Failure> check_run(const Spec& spec, const Machine& machine, const Image& image) {
  std::vector<Failure> failures;
  bool fault_expected = std::any_of(spec.expectations.begin(), spec.expectations.end(), [](const Expectation& e) {
    auto* s = std::get_if<ExpectStop>(&e.check);
    return s && s->kind == StopKind::Fault;
  });
  // A fault always fails a test unless the test expects it.
  if (machine.stop().kind == StopKind::Fault && !fault_expected) {
    const auto& f = *machine.stop().fault;
    failures.push_back({0, fmt::format("the program faulted in task {} at address {}: {}", f.task, f.address, f.message)});
  }
  // What follows the cut would be unchecked: the test cannot pass.
  if (machine.stop().kind == StopKind::EventLimit)
    failures.push_back({0, fmt::format("the run stopped at {} ms: {}; ask for less time with @for",
                                       machine.now_us() / kMicrosPerMs, event_limit_reason(machine))});
  for (const auto& e : spec.expectations) {
    if (auto why = check_one(e.check, machine, image))
      failures.push_back({e.line, fmt::format("expected {}; {}", e.text, *why)});
  }
  return failures;
}

}  // namespace rcx::semtest
