// Bytes as what a debugger client sends `rcxc debug`. The frames are read
// as `dap::serve` reads them (lsp/jsonrpc.h's framing) and handled by
// `dap::handle_text`, the program run by `dap::advance` between them, as
// serve does (without its reader thread: a pause request comes after at
// most 20 slices of a run, so a program that runs for hours of virtual time
// ends the input's turn). Every message written must be a DAP message
// (seq increasing from 1, type response or event; a response with
// request_seq, success and command, and a message when it failed; an event
// with its name), and every request must get exactly one response, in
// order.
//
// First byte: mode. Bit 0 clear: the rest is the raw byte stream. Set: the
// rest is JSON bodies separated by 0x1e, each framed with its exact
// Content-Length, so mutations reach the requests. Programs are read from
// wherever a fuzzed launch points (the seeds name examples/, relative to
// the repository's root, where scripts/fuzz-smoke runs).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dap/session.h"
#include "lsp/jsonrpc.h"

namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& why, const std::string& what) {
  std::fprintf(stderr, "fuzz_dap: %s\n%.4000s\n", why.c_str(), what.c_str());
  std::abort();
}

void check(const json& m, std::int64_t& last_seq, std::vector<std::int64_t>& answered) {
  if (!m.is_object() || !m.contains("seq") || !m["seq"].is_number_integer() || m["seq"].get<std::int64_t>() != last_seq + 1)
    fail("a message without the next seq", m.dump());
  last_seq = m["seq"];
  std::string type = m.contains("type") && m["type"].is_string() ? m["type"].get<std::string>() : "";
  if (type == "event") {
    if (!m.contains("event") || !m["event"].is_string()) fail("an event without its name", m.dump());
  } else if (type == "response") {
    if (!m.contains("request_seq") || !m["request_seq"].is_number_integer() || !m.contains("success") ||
        !m["success"].is_boolean() || !m.contains("command") || !m["command"].is_string())
      fail("a malformed response", m.dump());
    if (!m["success"].get<bool>() && (!m.contains("message") || !m["message"].is_string()))
      fail("a failed response without a message", m.dump());
    answered.push_back(m["request_seq"]);
  } else {
    fail("neither a response nor an event", m.dump());
  }
  if (!json::accept(m.dump(-1, ' ', false, json::error_handler_t::replace))) fail("a message that is no JSON text", m.dump());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string rest(reinterpret_cast<const char*>(data + 1), size - 1);
  std::string stream;
  if ((data[0] & 1) == 0) {
    stream = rest;
  } else {
    for (std::size_t start = 0; start <= rest.size();) {
      std::size_t end = rest.find('\x1e', start);
      if (end == std::string::npos) end = rest.size();
      std::string body = rest.substr(start, end - start);
      start = end + 1;
      stream += "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
    }
  }
  rcxc::dap::Session session;
  std::istringstream in(stream);
  std::int64_t last_seq = 0;
  std::vector<std::int64_t> asked, answered;
  auto take = [&](const std::vector<json>& messages) {
    for (const auto& m : messages) check(m, last_seq, answered);
  };
  while (!session.disconnected) {
    rcxc::lsp::Frame frame = rcxc::lsp::read_frame(in);
    if (frame.kind == rcxc::lsp::Frame::Kind::End) break;
    if (frame.kind != rcxc::lsp::Frame::Kind::Message) continue;
    json request = json::parse(frame.body, nullptr, false);
    bool is_request = request.is_object() && request.contains("type") && request["type"] == "request" &&
                      request.contains("command") && request["command"].is_string() &&
                      !request["command"].get<std::string>().empty();
    if (is_request)
      asked.push_back(request.contains("seq") && request["seq"].is_number_integer() ? request["seq"].get<std::int64_t>() : 0);
    take(rcxc::dap::handle_text(session, frame.body));
    for (int slice = 0; rcxc::dap::running(session); ++slice) {
      if (slice == 20) {
        take(rcxc::dap::handle(session, {{"seq", 0}, {"type", "request"}, {"command", "pause"}}));
        asked.push_back(0);
        break;
      }
      take(rcxc::dap::advance(session, 2000));
    }
  }
  if (asked != answered) fail("responses " + json(answered).dump() + " for requests " + json(asked).dump(), stream);
  return 0;
}
