#include "lsp/jsonrpc.h"

#include <algorithm>
#include <cctype>
#include <cstdint>

namespace rcxc::lsp {
namespace {

bool iequals_prefix(const std::string& line, const std::string& name) {
  if (line.size() < name.size()) return false;
  for (std::size_t i = 0; i < name.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(line[i])) != std::tolower(static_cast<unsigned char>(name[i])))
      return false;
  return true;
}

// One header line without its CRLF (a bare LF is accepted too); false at end
// of input before any character.
bool read_line(std::istream& in, std::string& line) {
  line.clear();
  int c;
  while ((c = in.get()) != EOF) {
    if (c == '\n') break;
    if (line.size() < 4096) line.push_back(static_cast<char>(c));
  }
  if (c == EOF && line.empty()) return false;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

std::string truncated(std::uint64_t length) {
  return "the input ended inside a message of " + std::to_string(length) + " bytes (its Content-Length)";
}

}  // namespace

Frame read_frame(std::istream& in) {
  std::string line;
  std::optional<std::uint64_t> length;
  std::string problem;
  bool any = false;
  while (true) {
    if (!read_line(in, line))
      return {Frame::Kind::End, "", any ? "the input ended inside a message's header" : ""};
    if (line.empty()) {
      if (!any) continue;  // stray blank lines between messages
      break;
    }
    any = true;
    if (iequals_prefix(line, "content-length:")) {
      std::string value = line.substr(15);
      std::uint64_t n = 0;
      bool digits = false, ok = true;
      for (char ch : value) {
        if (ch == ' ' || ch == '\t') continue;
        if (!std::isdigit(static_cast<unsigned char>(ch)) || n > kMaxSkip) {
          ok = false;
          break;
        }
        n = n * 10 + static_cast<std::uint64_t>(ch - '0');
        digits = true;
      }
      if (ok && digits && n <= kMaxSkip)
        length = n;
      else
        problem = "bad Content-Length '" + value + "'";
    } else if (line.find(':') == std::string::npos) {
      problem = "header line without ':'";
    }
  }
  if (!length) return {Frame::Kind::BadHeader, "", problem.empty() ? "no Content-Length header" : problem};
  if (*length > kMaxBody) {
    // Too large to hold, but the length is believable: reading past the
    // body keeps the next message's header where it is looked for. Taking
    // the body's first line for a header instead would lose the messages
    // after it too.
    for (std::uint64_t left = *length; left > 0 && in;) {
      auto step = static_cast<std::streamsize>(std::min<std::uint64_t>(left, std::uint64_t{1} << 30));
      in.ignore(step);
      left -= static_cast<std::uint64_t>(in.gcount());
      if (in.gcount() < step) return {Frame::Kind::End, "", truncated(*length)};
    }
    return {Frame::Kind::BadHeader, "",
            "a message of " + std::to_string(*length) + " bytes skipped (the limit is " + std::to_string(kMaxBody >> 20) +
                " MiB)"};
  }
  std::string body(*length, '\0');
  in.read(body.data(), static_cast<std::streamsize>(*length));
  if (static_cast<std::size_t>(in.gcount()) != *length) return {Frame::Kind::End, "", truncated(*length)};
  return {Frame::Kind::Message, std::move(body), ""};
}

void write_message(std::ostream& out, const nlohmann::json& message) {
  // Invalid UTF-8 in a file's text must not make dump() throw.
  std::string body = message.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  out << "Content-Length: " << body.size() << "\r\n\r\n" << body;
  out.flush();
}

nlohmann::json response(const nlohmann::json& id, nlohmann::json result) {
  return {{"jsonrpc", "2.0"}, {"id", id}, {"result", std::move(result)}};
}

nlohmann::json error_response(const nlohmann::json& id, int code, const std::string& message) {
  return {{"jsonrpc", "2.0"}, {"id", id}, {"error", {{"code", code}, {"message", message}}}};
}

nlohmann::json notification(const std::string& method, nlohmann::json params) {
  return {{"jsonrpc", "2.0"}, {"method", method}, {"params", std::move(params)}};
}

}  // namespace rcxc::lsp
