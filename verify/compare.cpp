#include "verify/compare.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <limits>
#include <map>

namespace rcx {
namespace {

// Events are compared per stream: what happens on output A is ordered, but
// whether A or C changed first within one instruction pair is not something
// a robot shows. Sounds and tones share one stream (the sound queue).
enum class Stream { OutputA, OutputB, OutputC, Sound, Display, Message, Datalog };

bool observable(const Event& e) {
  switch (e.kind) {
    case EventKind::Output: case EventKind::Sound: case EventKind::Tone: case EventKind::Display:
    case EventKind::MessageSent: case EventKind::Datalog:
      return true;
    default:
      return false;
  }
}

Stream stream_of(const Event& e) {
  switch (e.kind) {
    case EventKind::Output: return static_cast<Stream>(static_cast<int>(Stream::OutputA) + e.index);
    case EventKind::Sound: case EventKind::Tone: return Stream::Sound;
    case EventKind::Display: return Stream::Display;
    case EventKind::MessageSent: return Stream::Message;
    default: return Stream::Datalog;
  }
}

// What an event shows, as a value: runs are compared on these, and what()
// writes one out only for messages and the side by side (writing every
// event out, where a program that switches an output on every pass has
// thousands a second, was most of what `rcxc compare` spent).
struct Look {
  bool nothing = false;  // before the first event of a stream that has no rest state
  EventKind kind = EventKind::Output;
  int index = 0;
  OutputMode mode = OutputMode::Float;
  bool forward = false;
  int value = 0;   // output power, sound, frequency, display device, message, datalog value
  int duration = 0;
  bool operator==(const Look&) const = default;
};

Look look_of(const Event& e) {
  Look l{.kind = e.kind};
  switch (e.kind) {
    case EventKind::Output:
      l.index = e.index % 3;
      l.mode = e.output.mode;
      if (l.mode == OutputMode::On) {
        l.forward = e.output.dir == Direction::Forward;
        l.value = e.output.power;
      }
      return l;
    case EventKind::Tone: l.duration = e.duration; [[fallthrough]];
    case EventKind::Sound: case EventKind::Display: case EventKind::MessageSent: case EventKind::Datalog:
      l.value = e.value;
      return l;
    default: return l;
  }
}

std::string what(const Event& e) {
  const Look l = look_of(e);
  switch (l.kind) {
    case EventKind::Output:
      if (l.mode != OutputMode::On) return fmt::format("output {} {}", "ABC"[l.index], to_string(l.mode));
      return fmt::format("output {} on {} {}", "ABC"[l.index], l.forward ? "fwd" : "rev", l.value);
    case EventKind::Sound: return fmt::format("sound {}", l.value);
    case EventKind::Tone: return fmt::format("tone {} {}", l.value, l.duration);
    case EventKind::Display: return fmt::format("display {}", l.value);
    case EventKind::MessageSent: return fmt::format("send {}", l.value);
    case EventKind::Datalog: return fmt::format("datalog {}", l.value);
    default: return to_string(l.kind);
  }
}

// "1st", "2nd", "3rd", "11th", "42nd".
std::string ordinal_text(int n) {
  const int tens = n % 100, ones = n % 10;
  const char* suffix = tens >= 11 && tens <= 13 ? "th" : ones == 1 ? "st" : ones == 2 ? "nd" : ones == 3 ? "rd" : "th";
  return fmt::format("{}{}", n, suffix);
}

Micros allowance(const TimeTolerance& tol, Micros t) {
  return tol.absolute_us + static_cast<Micros>(tol.relative * static_cast<double>(t));
}

std::string line_of(const Event& e) { return fmt::format("{}ms {}", e.t_us / kMicrosPerMs, what(e)); }

// The observable events of a run. An output's direction and power show
// only while it runs: changing them while it is off or floating changes
// nothing a robot does (the next "on" shows them), so such events are left
// out, as are events that leave what shows unchanged.
// What output `o` shows before any event: it floats.
Look at_rest(std::size_t o) { return {.kind = EventKind::Output, .index = static_cast<int>(o % kOutputs)}; }

std::vector<const Event*> visible_events(const Machine& m) {
  std::array<Look, kOutputs> shown;
  for (std::size_t o = 0; o < kOutputs; ++o) shown[o] = at_rest(o);
  std::vector<const Event*> out;
  for (const auto& e : m.state().events) {
    if (!observable(e)) continue;
    if (e.kind == EventKind::Output) {
      Look now = look_of(e);
      auto o = static_cast<std::size_t>(e.index) % kOutputs;
      if (now == shown[o]) continue;
      shown[o] = now;
    }
    out.push_back(&e);
  }
  return out;
}

// One run's events of one stream, walked while comparing: a running
// output's state that the next running state replaces within `glitch_us`
// may be passed over (command order, not behaviour), and then so may a
// state equal to the one before it.
struct StreamWalk {
  const std::vector<const Event*>* list;
  Micros glitch_us;
  std::size_t at = 0;
  Look shown;  // what the last event taken shows

  const std::vector<const Event*>& events() const { return *list; }
  bool done() const { return at >= events().size(); }
  const Event& here() const { return *events()[at]; }
  bool running(const Event& e) const { return e.kind == EventKind::Output && e.output.mode == OutputMode::On; }
  // Passes over the glitch here, if it is one, and any repeat after it.
  bool skip_glitch() {
    if (done() || at + 1 >= events().size() || !running(here())) return false;
    const Event& next = *events()[at + 1];
    if (!running(next) || next.t_us - here().t_us > glitch_us) return false;
    ++at;
    while (!done() && look_of(here()) == shown) ++at;
    return true;
  }
  void take() { shown = look_of(*events()[at++]); }
};

// How many events two walks agree on from here (up to `limit`), taking
// glitches as they come.
int agreement(StreamWalk a, StreamWalk b, int limit);

// Where two walks disagree: passes over a glitch on one side, or on both,
// choosing whichever lets the runs agree longest after it (a state that
// is a glitch in one run may hold longer in the other; `shallow`: only
// whether they agree right after it). False when no glitch helps.
bool pass_over_glitches(StreamWalk& a, StreamWalk& b, bool shallow = false) {
  constexpr int kLookahead = 8;
  StreamWalk a2 = a, b2 = b;
  bool skip_a = a2.skip_glitch(), skip_b = b2.skip_glitch();
  int best = 0;
  int choice = -1;
  auto consider = [&](int option, const StreamWalk& x, const StreamWalk& y) {
    int n = shallow ? (x.done() || y.done() || look_of(x.here()) == look_of(y.here()) ? 1 : 0) : agreement(x, y, kLookahead);
    if (n > best) {
      best = n;
      choice = option;
    }
  };
  if (skip_a) consider(0, a2, b);
  if (skip_b) consider(1, a, b2);
  if (skip_a && skip_b) consider(2, a2, b2);
  if (choice < 0) return false;
  if (choice != 1) a = a2;
  if (choice != 0) b = b2;
  return true;
}

int agreement(StreamWalk a, StreamWalk b, int limit) {
  int n = 0;
  while (n < limit) {
    if (a.done() || b.done()) return n + 1;  // the rest is the caller's to judge
    if (look_of(a.here()) != look_of(b.here())) {
      if (!pass_over_glitches(a, b, true)) return n;
      continue;
    }
    a.take();
    b.take();
    ++n;
  }
  return n;
}

std::map<Stream, std::vector<const Event*>> streams(const Machine& m) {
  std::map<Stream, std::vector<const Event*>> out;
  for (const Event* e : visible_events(m)) out[stream_of(*e)].push_back(e);
  return out;
}

// The value of each variable the image names. A name given to several
// variables (nqc names a local like the global it shadows) says nothing
// about which is which, so it is left out.
std::map<std::string, int> globals(const Machine& m, const Image& image) {
  std::map<std::string, int> out;
  std::map<std::string, int> uses;
  for (const auto& s : image.symbols)
    if (s.type == SymbolType::Variable) {
      out[s.name] = m.state().vars[s.index];
      ++uses[s.name];
    }
  for (const auto& [name, n] : uses)
    if (n > 1) out.erase(name);
  return out;
}

// The value of each of `names` the image gives a variable: the first
// variable symbol of that name, which is the file-scope one (compare.h).
std::map<std::string, int> globals(const Machine& m, const Image& image, const std::vector<std::string>& names) {
  std::map<std::string, int> out;
  for (const auto& s : image.symbols)
    if (s.type == SymbolType::Variable && !out.contains(s.name) &&
        std::find(names.begin(), names.end(), s.name) != names.end())
      out[s.name] = m.state().vars[s.index];
  return out;
}

// The first row at which both runs' visible events show something else,
// times aside (the row count when they show the same events in the same
// order), and with Write both lists side by side (`*` where a row differs).
void side_by_side(const RunView& a, const RunView& b, SideBySide write, RunComparison& r) {
  auto ea = visible_events(*a.machine), eb = visible_events(*b.machine);
  std::size_t row = 0;
  while (row < ea.size() && row < eb.size() && look_of(*ea[row]) == look_of(*eb[row])) ++row;
  r.first_unlike_row = row;
  if (write == SideBySide::Skip) return;
  std::vector<std::string> la, lb;
  for (const Event* e : ea) la.push_back(line_of(*e));
  for (const Event* e : eb) lb.push_back(line_of(*e));
  std::size_t width = a.label.size();
  for (const auto& l : la) width = std::max(width, l.size());
  // Padded by hand: the lines are ASCII, and fmt's padding decodes UTF-8.
  auto padded = [width](const std::string& x) { return x + std::string(width - std::min(width, x.size()), ' '); };
  std::string out = "  " + padded(a.label) + "  | " + b.label + "\n";
  for (std::size_t i = 0; i < std::max(la.size(), lb.size()); ++i) {
    const std::string& x = i < la.size() ? la[i] : "";
    const std::string& y = i < lb.size() ? lb[i] : "";
    out += x == y ? ' ' : '*';
    out += ' ';
    out += padded(x);
    out += "  | ";
    out += y;
    out += '\n';
  }
  r.side_by_side = std::move(out);
}

}  // namespace

std::vector<std::string> observable_lines(const Machine& machine) {
  std::vector<std::string> out;
  for (const Event* e : visible_events(machine)) out.push_back(line_of(*e));
  return out;
}

std::optional<Micros> parting_time(const Machine& a, const Machine& b, Micros from_us) {
  auto va = visible_events(a), vb = visible_events(b);
  std::size_t i = 0;
  for (; i < va.size() && i < vb.size(); ++i) {
    const Event& ea = *va[i];
    const Event& eb = *vb[i];
    if (ea.t_us == eb.t_us && look_of(ea) == look_of(eb)) continue;
    Micros t = std::min(ea.t_us, eb.t_us);
    // Before `from_us` the inputs were the same, so the runs were too.
    return std::max(t, from_us);
  }
  if (i < va.size()) return std::max(va[i]->t_us, from_us);
  if (i < vb.size()) return std::max(vb[i]->t_us, from_us);
  return std::nullopt;
}

const char* stream_name(int stream) {
  static constexpr std::array<const char*, kEventStreams> kNames = {"output A", "output B", "output C", "sounds",
                                                                    "display", "messages sent", "datalog"};
  return stream >= 0 && stream < kEventStreams ? kNames[static_cast<std::size_t>(stream)] : "events";
}

namespace {

std::string ms_text(Micros us) { return fmt::format("{:.1f} ms", static_cast<double>(us) / kMicrosPerMs); }

std::string us_text(Micros us) { return fmt::format("{} us an instruction", us); }

}  // namespace

TimingVerdict timing_cause(const RunComparison& at_cost, Micros cost_us, const RunComparison& shorter,
                           Micros shorter_cost_us) {
  auto pairing = [](const RunComparison& r, int s) -> const StreamPairing& {
    return r.streams[static_cast<std::size_t>(s)];
  };
  // Only the events are judged: the rerun may have been cut short of the
  // runs' ends, where their final values and how they stopped are known.
  for (int s = 0; s < kEventStreams; ++s)
    if (pairing(shorter, s).unlike)
      return {TimingCause::Undecided,
              fmt::format("{}: at {} the runs show other events", stream_name(s), us_text(shorter_cost_us))};
  // A difference of speed parts later at the shorter time, or never: a stream
  // that parts as soon or sooner says the difference is not one of speed.
  for (int s = 0; s < kEventStreams; ++s) {
    const StreamPairing& slow = pairing(at_cost, s);
    const StreamPairing& fast = pairing(shorter, s);
    if (!fast.parted_at || (slow.parted_at ? *fast.parted_at > *slow.parted_at : *fast.parted_at >= slow.pairs))
      continue;
    auto apart = [](const StreamPairing& p) { return ms_text(std::llabs(p.parted_times.a_us - p.parted_times.b_us)); };
    std::string before = slow.parted_at == fast.parted_at ? fmt::format("{} apart at {}", apart(slow), us_text(cost_us))
                                                          : fmt::format("within the tolerance at {}", us_text(cost_us));
    return {TimingCause::NotSpeed,
            fmt::format("{}: the {} event both show ({}) is {} and {} apart at {}", stream_name(s),
                        ordinal_text(*fast.parted_at + 1), fast.parted_event, before, apart(fast),
                        us_text(shorter_cost_us))};
  }
  for (int s = 0; s < kEventStreams; ++s) {
    const StreamPairing& slow = pairing(at_cost, s);
    const StreamPairing& fast = pairing(shorter, s);
    if (slow.parted_at && !fast.parted_at && fast.pairs <= *slow.parted_at)
      return {TimingCause::Undecided,
              fmt::format("{}: at {} the runs show only {} event(s) in the same order, not the {} that parted",
                          stream_name(s), us_text(shorter_cost_us), fast.pairs, ordinal_text(*slow.parted_at + 1))};
  }
  return {TimingCause::Speed, ""};
}

TimingDifference timing_difference(const std::vector<MatchedEvent>& matched) {
  TimingDifference d;
  double sooner = 0;
  for (const auto& m : matched) {
    sooner += static_cast<double>(m.b_us - m.a_us);
    d.worst_later_us = std::max(d.worst_later_us, m.a_us - m.b_us);
  }
  d.events = static_cast<int>(matched.size());
  if (d.events > 0) d.mean_sooner_us = sooner / d.events;
  return d;
}

// A run cut short, by the time limit or by its event log filling, stopped
// at an arbitrary point of whatever it was doing.
bool cut_off(const Machine& m) {
  return m.stop().kind == StopKind::TimeLimit || m.stop().kind == StopKind::EventLimit;
}

RunComparison compare_runs(const RunView& a, const RunView& b, TimeTolerance tol,
                           const std::optional<std::vector<std::string>>& global_names, SideBySide write) {
  RunComparison r;
  // Events are compared up to where a run was cut off by the time limit;
  // a run that ended has shown everything it would, so what the other shows
  // after that end is a difference.
  Micros end_us = std::numeric_limits<Micros>::max();
  for (const Machine* m : {a.machine, b.machine})
    if (cut_off(*m)) end_us = std::min(end_us, m->now_us());
  auto sa = streams(*a.machine), sb = streams(*b.machine);
  std::size_t timing_differences = 0;
  for (int s = 0; s <= static_cast<int>(Stream::Datalog); ++s) {
    // Once this stream's times have parted beyond the tolerance, the walk
    // goes on to see whether anything but time differs; `drift` is how far
    // apart they have been, which also widens the cut-off below.
    bool parted = false;
    Micros drift = 0;
    // Outputs start floating; other streams start with nothing shown.
    Look start = s <= static_cast<int>(Stream::OutputC) ? at_rest(static_cast<std::size_t>(s)) : Look{.nothing = true};
    StreamWalk wa{&sa[static_cast<Stream>(s)], tol.glitch_us, 0, start};
    StreamWalk wb{&sb[static_cast<Stream>(s)], tol.glitch_us, 0, start};
    while (!wa.done() || !wb.done()) {
      if (wa.done() || wb.done()) {
        if (wa.done() ? wb.skip_glitch() : wa.skip_glitch()) continue;
        const Event& extra = wa.done() ? wb.here() : wa.here();
        // The other run may simply have been cut off just before it.
        if (end_us != std::numeric_limits<Micros>::max() && extra.t_us >= end_us - allowance(tol, end_us) - drift)
          break;
        r.differences.push_back(fmt::format("only {} has: {}", wa.done() ? b.label : a.label, line_of(extra)));
        r.streams[static_cast<std::size_t>(s)].unlike = true;
        break;
      }
      const Event& ea = wa.here();
      const Event& eb = wb.here();
      if (look_of(ea) != look_of(eb)) {
        if (pass_over_glitches(wa, wb)) continue;
        r.differences.push_back(fmt::format("{}: {}  vs  {}: {}", a.label, line_of(ea), b.label, line_of(eb)));
        r.streams[static_cast<std::size_t>(s)].unlike = true;
        break;
      }
      auto allowed = allowance(tol, std::max(ea.t_us, eb.t_us));
      Micros apart = std::llabs(ea.t_us - eb.t_us);
      if (apart > allowed && !parted) {
        r.differences.push_back(fmt::format("{} at {}ms ({}) but {}ms ({}); allowed difference {}ms", what(ea),
                                            ea.t_us / kMicrosPerMs, a.label, eb.t_us / kMicrosPerMs, b.label,
                                            allowed / kMicrosPerMs));
        ++timing_differences;
        parted = true;
      }
      StreamPairing& pairing = r.streams[static_cast<std::size_t>(s)];
      if (apart > allowed && !pairing.parted_at) {
        pairing.parted_at = pairing.pairs;
        pairing.parted_event = what(ea);
        pairing.parted_times = {ea.t_us, eb.t_us};
      }
      ++pairing.pairs;
      if (!parted) r.matched.push_back({ea.t_us, eb.t_us});
      drift = std::max(drift, apart);
      r.most_sooner_us = std::max(r.most_sooner_us, eb.t_us - ea.t_us);
      r.most_later_us = std::max(r.most_later_us, ea.t_us - eb.t_us);
      ++r.in_order;
      wa.take();
      wb.take();
    }
  }
  // Final values mean something only for runs that ended: a program still
  // looping at the time limit was cut at an arbitrary point of its loop.
  // Names in one image only (a parameter nqc keeps as a variable, a global
  // rcxc removed as unused) are not compared.
  bool both_ended = !cut_off(*a.machine) && !cut_off(*b.machine);
  if (both_ended) {
    auto values = [&](const RunView& v) {
      return global_names ? globals(*v.machine, *v.image, *global_names) : globals(*v.machine, *v.image);
    };
    auto ga = values(a), gb = values(b);
    for (const auto& [name, va] : ga) {
      auto it = gb.find(name);
      if (it != gb.end() && it->second != va)
        r.differences.push_back(fmt::format("global '{}' = {} ({}) but {} ({})", name, va, a.label, it->second, b.label));
    }
  }
  // One run ending just after the other was cut off is the same boundary
  // effect as an event just after the cut-off.
  auto cut_before_end = [&](const Machine& cut, const Machine& ended) {
    return cut_off(cut) && ended.stop().kind == StopKind::Ended &&
           ended.now_us() >= cut.now_us() - allowance(tol, cut.now_us());
  };
  bool both_cut = cut_off(*a.machine) && cut_off(*b.machine);
  if (a.machine->stop().kind != b.machine->stop().kind && !both_cut && !cut_before_end(*a.machine, *b.machine) &&
      !cut_before_end(*b.machine, *a.machine))
    r.differences.push_back(fmt::format("{} stopped with '{}', {} with '{}'", a.label, to_string(a.machine->stop().kind),
                                        b.label, to_string(b.machine->stop().kind)));
  r.same = r.differences.empty();
  r.timing_only = !r.same && timing_differences == r.differences.size();
  if (!r.same) side_by_side(a, b, write, r);
  return r;
}

}  // namespace rcx
