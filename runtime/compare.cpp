#include "runtime/compare.h"

#include <fmt/format.h>

#include <algorithm>
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

std::string what(const Event& e) {
  switch (e.kind) {
    case EventKind::Output:
      return fmt::format("output {} {} {} {}", "ABC"[e.index % 3], to_string(e.output.mode),
                         e.output.dir == Direction::Forward ? "fwd" : "rev", e.output.power);
    case EventKind::Sound: return fmt::format("sound {}", e.value);
    case EventKind::Tone: return fmt::format("tone {} {}", e.value, e.duration);
    case EventKind::Display: return fmt::format("display {}", e.value);
    case EventKind::MessageSent: return fmt::format("send {}", e.value);
    case EventKind::Datalog: return fmt::format("datalog {}", e.value);
    default: return to_string(e.kind);
  }
}

Micros allowance(const TimeTolerance& tol, Micros t) {
  return tol.absolute_us + static_cast<Micros>(tol.relative * static_cast<double>(t));
}

std::string line_of(const Event& e) { return fmt::format("{}ms {}", e.t_us / kMicrosPerMs, what(e)); }

std::map<Stream, std::vector<const Event*>> streams(const Machine& m) {
  std::map<Stream, std::vector<const Event*>> out;
  for (const auto& e : m.state().events)
    if (observable(e)) out[stream_of(e)].push_back(&e);
  return out;
}

std::map<std::string, int> globals(const Machine& m, const Image& image) {
  std::map<std::string, int> out;
  for (const auto& s : image.symbols)
    if (s.type == SymbolType::Variable) out[s.name] = m.state().vars[s.index];
  return out;
}

std::string side_by_side(const RunView& a, const RunView& b) {
  auto la = observable_lines(*a.machine), lb = observable_lines(*b.machine);
  std::size_t width = a.label.size();
  for (const auto& l : la) width = std::max(width, l.size());
  std::string out = fmt::format("  {:<{}}  | {}\n", a.label, width, b.label);
  for (std::size_t i = 0; i < std::max(la.size(), lb.size()); ++i) {
    const std::string& x = i < la.size() ? la[i] : "";
    const std::string& y = i < lb.size() ? lb[i] : "";
    out += fmt::format("{} {:<{}}  | {}\n", x == y ? ' ' : '*', x, width, y);
  }
  return out;
}

}  // namespace

std::vector<std::string> observable_lines(const Machine& machine) {
  std::vector<std::string> out;
  for (const auto& e : machine.state().events)
    if (observable(e)) out.push_back(line_of(e));
  return out;
}

RunComparison compare_runs(const RunView& a, const RunView& b, TimeTolerance tol) {
  RunComparison r;
  const Micros end_us = std::min(a.machine->now_us(), b.machine->now_us());
  auto sa = streams(*a.machine), sb = streams(*b.machine);
  for (int s = 0; s <= static_cast<int>(Stream::Datalog); ++s) {
    const auto& xa = sa[static_cast<Stream>(s)];
    const auto& xb = sb[static_cast<Stream>(s)];
    for (std::size_t i = 0; i < std::max(xa.size(), xb.size()); ++i) {
      if (i >= xa.size() || i >= xb.size()) {
        const Event* extra = i < xa.size() ? xa[i] : xb[i];
        // The other run may simply have been cut off just before it.
        if (extra->t_us >= end_us - allowance(tol, end_us)) break;
        r.differences.push_back(fmt::format("only {} has: {}", i < xa.size() ? a.label : b.label, line_of(*extra)));
        break;
      }
      const Event& ea = *xa[i];
      const Event& eb = *xb[i];
      if (what(ea) != what(eb)) {
        r.differences.push_back(fmt::format("{}: {}  vs  {}: {}", a.label, line_of(ea), b.label, line_of(eb)));
        break;
      }
      auto allowed = allowance(tol, std::max(ea.t_us, eb.t_us));
      if (std::llabs(ea.t_us - eb.t_us) > allowed) {
        r.differences.push_back(fmt::format("{} at {}ms ({}) but {}ms ({}); allowed difference {}ms", what(ea),
                                            ea.t_us / kMicrosPerMs, a.label, eb.t_us / kMicrosPerMs, b.label,
                                            allowed / kMicrosPerMs));
        break;
      }
    }
  }
  // Final values mean something only for runs that ended: a program still
  // looping at the time limit was cut at an arbitrary point of its loop.
  // Names in one image only (a parameter nqc keeps as a variable, a global
  // rcxc removed as unused) are not compared.
  bool both_ended = a.machine->stop().kind != StopKind::TimeLimit && b.machine->stop().kind != StopKind::TimeLimit;
  if (both_ended) {
    auto ga = globals(*a.machine, *a.image), gb = globals(*b.machine, *b.image);
    for (const auto& [name, va] : ga) {
      auto it = gb.find(name);
      if (it != gb.end() && it->second != va)
        r.differences.push_back(fmt::format("global '{}' = {} ({}) but {} ({})", name, va, a.label, it->second, b.label));
    }
  }
  // One run ending just after the other was cut off by the time limit is
  // the same boundary effect as an event just after the cut-off.
  auto cut_before_end = [&](const Machine& cut, const Machine& ended) {
    return cut.stop().kind == StopKind::TimeLimit && ended.stop().kind == StopKind::Ended &&
           ended.now_us() >= cut.now_us() - allowance(tol, cut.now_us());
  };
  if (a.machine->stop().kind != b.machine->stop().kind && !cut_before_end(*a.machine, *b.machine) &&
      !cut_before_end(*b.machine, *a.machine))
    r.differences.push_back(fmt::format("{} stopped with '{}', {} with '{}'", a.label, to_string(a.machine->stop().kind),
                                        b.label, to_string(b.machine->stop().kind)));
  r.same = r.differences.empty();
  if (!r.same) r.side_by_side = side_by_side(a, b);
  return r;
}

}  // namespace rcx
