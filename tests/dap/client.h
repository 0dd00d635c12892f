// A scripted DAP client for the tests of tests/dap/: a real `rcxc debug`
// process on pipes, requests in, responses and events out. Every wait has a
// deadline, so an adapter that hangs fails the test instead of stalling it.
#pragma once

#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace rcxc::dap::test {

using nlohmann::json;

inline std::string framed(const std::string& body) {
  return "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}

class Client {
 public:
  Client() {
    int to_child[2], from_child[2], err_child[2];
    if (pipe(to_child) != 0 || pipe(from_child) != 0 || pipe(err_child) != 0) ADD_FAILURE() << "pipe";
    pid_ = fork();
    if (pid_ == 0) {
      dup2(to_child[0], 0);
      dup2(from_child[1], 1);
      dup2(err_child[1], 2);
      for (int fd : {to_child[0], to_child[1], from_child[0], from_child[1], err_child[0], err_child[1]}) close(fd);
      execl(RCXC_BINARY, RCXC_BINARY, "debug", static_cast<char*>(nullptr));
      _exit(127);
    }
    close(to_child[0]);
    close(from_child[1]);
    close(err_child[1]);
    in_ = to_child[1];
    out_ = from_child[0];
    err_ = err_child[0];
    signal(SIGPIPE, SIG_IGN);
  }
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;
  ~Client() {
    if (in_ >= 0) close(in_);
    if (pid_ > 0 && exit_code_ < 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (out_ >= 0) close(out_);
    if (err_ >= 0) close(err_);
  }

  void write_raw(const std::string& bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
      ssize_t n = write(in_, bytes.data() + done, bytes.size() - done);
      if (n <= 0) {
        ADD_FAILURE() << "rcxc debug does not read its input";
        return;
      }
      done += static_cast<std::size_t>(n);
    }
  }

  int send(const std::string& command, json arguments = json::object()) {
    int seq = ++seq_;
    write_raw(framed(json{{"seq", seq}, {"type", "request"}, {"command", command}, {"arguments", arguments}}.dump()));
    return seq;
  }

  // The response to request `seq`; events read meanwhile are kept.
  json response(int seq) {
    for (;;) {
      json m = next();
      if (m.is_null()) return m;
      if (m.value("type", "") == "response" && m.value("request_seq", -1) == seq) return m;
      if (m.value("type", "") == "event") events_.push_back(m);
    }
  }
  json ask(const std::string& command, json arguments = json::object()) { return response(send(command, arguments)); }
  // The body of a successful response (a failure fails the test).
  json body(const std::string& command, json arguments = json::object()) {
    json r = ask(command, arguments);
    EXPECT_TRUE(r.value("success", false)) << command << ": " << r.dump();
    return r.value("body", json::object());
  }

  // The next event named `name` (the others before it are dropped, output
  // events kept in `outputs`).
  json event(const std::string& name) { return event_of({name}); }
  json event_of(const std::vector<std::string>& names) {
    for (;;) {
      json m;
      if (!events_.empty()) {
        m = events_.front();
        events_.pop_front();
      } else {
        m = next();
        if (m.is_null()) return m;
        if (m.value("type", "") != "event") continue;
      }
      if (m["event"] == "output") outputs.push_back(m["body"]);
      if (std::find(names.begin(), names.end(), m["event"]) != names.end()) return m;
    }
  }

  // Initialize and launch with `arguments`, then breakpoints at `lines` of
  // `file`, then configurationDone. Returns the breakpoints' answers.
  json start(const json& launch, const std::string& file = "", const std::vector<int>& lines = {}) {
    body("initialize", {{"adapterID", "rcxc"}, {"linesStartAt1", true}});
    json r = ask("launch", launch);
    EXPECT_TRUE(r.value("success", false)) << r.dump();
    EXPECT_FALSE(event("initialized").is_null());
    json placed;
    if (!file.empty()) {
      json bps = json::array();
      for (int l : lines) bps.push_back({{"line", l}});
      placed = body("setBreakpoints", {{"source", {{"path", file}}}, {"breakpoints", bps}})["breakpoints"];
    }
    body("configurationDone");
    return placed;
  }

  // Where thread `thread` is: its frames as (name, line).
  std::vector<std::pair<std::string, int>> frames(int thread) {
    std::vector<std::pair<std::string, int>> out;
    json trace = body("stackTrace", {{"threadId", thread}});  // kept: a loop over a temporary's member would dangle
    for (const auto& f : trace["stackFrames"]) out.emplace_back(f["name"], f["line"]);
    return out;
  }
  int line(int thread) {
    auto f = frames(thread);
    return f.empty() ? -1 : f[0].second;
  }

  // name -> value of the variables behind `ref`.
  std::map<std::string, std::string> variables(int ref) {
    std::map<std::string, std::string> out;
    json vars = body("variables", {{"variablesReference", ref}});
    for (const auto& v : vars["variables"]) out[v["name"]] = v["value"];
    return out;
  }
  // The variablesReference of the scope `name` of the top frame of `thread`.
  int scope(int thread, const std::string& name) {
    auto frames = body("stackTrace", {{"threadId", thread}})["stackFrames"];
    if (frames.empty()) return 0;
    json scopes = body("scopes", {{"frameId", frames[0]["id"]}});
    for (const auto& s : scopes["scopes"])
      if (s["name"] == name) return s["variablesReference"];
    return 0;
  }

  // Closes the input and returns the exit code (-1 if it did not end in 10 s).
  int finish() {
    if (in_ >= 0) close(in_);
    in_ = -1;
    auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (std::chrono::steady_clock::now() < deadline) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        return exit_code_;
      }
      usleep(10'000);
    }
    return -1;
  }
  // What it wrote on stderr (after finish()).
  std::string errors() {
    std::string text;
    char buf[4096];
    fcntl(err_, F_SETFL, O_NONBLOCK);
    for (ssize_t n; (n = read(err_, buf, sizeof buf)) > 0;) text.append(buf, static_cast<std::size_t>(n));
    return text;
  }

  std::vector<json> outputs;  // the bodies of output events seen

 private:
  // One message, or null after 10 s without one (or at end of output).
  json next() {
    for (;;) {
      auto end = buffer_.find("\r\n\r\n");
      if (end != std::string::npos) {
        auto at = buffer_.find("Content-Length: ");
        std::size_t length = std::stoul(buffer_.substr(at + 16, end - at - 16));
        if (buffer_.size() >= end + 4 + length) {
          json m = json::parse(buffer_.substr(end + 4, length));
          buffer_.erase(0, end + 4 + length);
          return m;
        }
      }
      pollfd p{out_, POLLIN, 0};
      if (poll(&p, 1, 10'000) <= 0) {
        ADD_FAILURE() << "rcxc debug said nothing for 10 s";
        return nullptr;
      }
      char buf[65536];
      ssize_t n = read(out_, buf, sizeof buf);
      if (n <= 0) {
        ADD_FAILURE() << "rcxc debug's output ended";
        return nullptr;
      }
      buffer_.append(buf, static_cast<std::size_t>(n));
    }
  }

  int pid_ = -1, in_ = -1, out_ = -1, err_ = -1;
  int seq_ = 0;
  int exit_code_ = -1;
  std::string buffer_;
  std::deque<json> events_;
};

}  // namespace rcxc::dap::test
