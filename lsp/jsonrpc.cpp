#include "lsp/jsonrpc.h"

#include <algorithm>
#include <cctype>
#include <cstdint>

namespace rcxc::lsp {

int json_nesting(std::string_view text) {
  int depth = 0, most = 0;
  bool in_string = false, escaped = false;
  for (char c : text) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      most = std::max(most, ++depth);
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return most;
}
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

// The value of a Content-Length header (what follows the colon), or
// nullopt when it is not a number or is past belief.
std::optional<std::uint64_t> content_length(const std::string& value) {
  std::uint64_t n = 0;
  bool digits = false;
  for (char ch : value) {
    if (ch == ' ' || ch == '\t') continue;
    if (!std::isdigit(static_cast<unsigned char>(ch)) || n > kMaxSkip) return std::nullopt;
    n = n * 10 + static_cast<std::uint64_t>(ch - '0');
    digits = true;
  }
  if (!digits || n > kMaxSkip) return std::nullopt;
  return n;
}

// Reads past `length` bytes; false when the input ends first.
bool skip(std::istream& in, std::uint64_t length) {
  for (std::uint64_t left = length; left > 0;) {
    auto step = static_cast<std::streamsize>(std::min<std::uint64_t>(left, std::uint64_t{1} << 30));
    in.ignore(step);
    left -= static_cast<std::uint64_t>(in.gcount());
    if (in.gcount() < step) return false;
  }
  return true;
}

// After a header that gave two lengths the body is passed over as the
// shorter says when those bytes are JSON text whole (no proper beginning of
// an object is), else as the longer says. Either way the message is
// refused: a guess that ran the wrong text would be worse than none.
Frame refuse_two_lengths(std::istream& in, std::uint64_t a, std::uint64_t b) {
  std::uint64_t shorter = std::min(a, b), longer = std::max(a, b);
  Frame refused{Frame::Kind::BadHeader, "",
                "Content-Length given twice, as " + std::to_string(a) + " and " + std::to_string(b) +
                    ": where the message ends is not known"};
  if (shorter > kMaxBody) return skip(in, longer) ? refused : Frame{Frame::Kind::End, "", truncated(longer)};
  std::string body(shorter, '\0');
  in.read(body.data(), static_cast<std::streamsize>(shorter));
  if (static_cast<std::size_t>(in.gcount()) != shorter) return {Frame::Kind::End, "", truncated(shorter)};
  if (nlohmann::json::accept(body) || skip(in, longer - shorter)) return refused;
  return {Frame::Kind::End, "", truncated(longer)};
}

}  // namespace

Frame read_frame(std::istream& in) {
  std::string line;
  std::optional<std::uint64_t> length, second_length;
  std::string problem, remark;
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
      auto n = content_length(value);
      if (!n) {
        problem = "bad Content-Length '" + value + "'";
        remark = problem + " ignored: another gives the length";
      } else if (length && *n != *length) {
        second_length = n;
      } else {
        // The same length twice is one length, as HTTP may take it (RFC
        // 9110, 8.6), but it is said: LSP asks for the header once.
        if (length) remark = "Content-Length given twice, as " + std::to_string(*n) + " both times: read as one";
        length = n;
      }
    } else if (line.find(':') == std::string::npos) {
      problem = "header line without ':'";
    }
  }
  if (length && second_length) return refuse_two_lengths(in, *length, *second_length);
  if (!length) return {Frame::Kind::BadHeader, "", problem.empty() ? "no Content-Length header" : problem};
  if (*length > kMaxBody) {
    // Too large to hold, but the length is believable: reading past the
    // body keeps the next message's header where it is looked for. Taking
    // the body's first line for a header instead would lose the messages
    // after it too.
    if (!skip(in, *length)) return {Frame::Kind::End, "", truncated(*length)};
    return {Frame::Kind::BadHeader, "",
            "a message of " + std::to_string(*length) + " bytes skipped (the limit is " + std::to_string(kMaxBody >> 20) +
                " MiB)"};
  }
  std::string body(*length, '\0');
  in.read(body.data(), static_cast<std::streamsize>(*length));
  if (static_cast<std::size_t>(in.gcount()) != *length) return {Frame::Kind::End, "", truncated(*length)};
  return {Frame::Kind::Message, std::move(body), remark};
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
