// NXT round trips over a pseudo-terminal: the host client on the slave, the
// virtual NXT served on the master in a thread, as `rcxc nxt brick --pty`
// does. What is measured is the host's whole time per command (encode,
// frame, pty both ways, the virtual brick, decode): a real brick adds its
// own link time (about 60 ms per reply on Bluetooth, a few ms on USB).
// Counters p50_us and p99_us are per-round-trip percentiles; the goal is
// p99 under 1 ms of host overhead.
//
// The kernel's part is measured beside it: each iteration also makes one
// bare round trip of the same bytes over a second pty whose other end only
// echoes them back (bare_p50_us, bare_p99_us): no code of ours but a write,
// a poll and a read on each side. A pty hands every write to a kernel
// worker thread, which on a busy machine waits for a CPU; that wait is the
// tail both columns share. overhead_p50_us is the median of (ours - bare)
// per iteration: what our code adds. BM_InProcess is client and brick
// without any pty, BM_BrickAnswer the virtual brick's own processing.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <fcntl.h>
#include <poll.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "nxt/client.h"
#include "nxt/virtual_nxt.h"

namespace {

using namespace nxt;

struct PtyServer {
  VirtualNxt brick = make_virtual_nxt();
  PtyPair pty;
  int stop[2] = {-1, -1};
  std::thread thread;
  PtyServer() {
    pty = std::get<PtyPair>(open_pty_pair());
    if (::pipe(stop) != 0) std::abort();
    ServeOptions options;
    options.stop_fd = stop[0];
    thread = std::thread([this, options] { serve(brick, pty.master_fd, options); });
  }
  ~PtyServer() {
    (void)!::write(stop[1], "x", 1);
    thread.join();
    ::close(stop[0]);
    ::close(stop[1]);
    close_pty_pair(pty);
  }
};

// The other end of a pty that sends back what it gets, `reply_bytes` for
// every `request_bytes`: the kernel's pty path with nothing of ours on it.
struct EchoServer {
  PtyPair pty;
  int stop[2] = {-1, -1};
  std::thread thread;
  EchoServer(std::size_t request_bytes, std::size_t reply_bytes) {
    pty = std::get<PtyPair>(open_pty_pair());
    if (::pipe(stop) != 0) std::abort();
    thread = std::thread([this, request_bytes, reply_bytes] {
      std::uint8_t buf[512] = {};
      std::size_t got = 0;
      while (true) {
        pollfd p[2] = {{pty.master_fd, POLLIN, 0}, {stop[0], POLLIN, 0}};
        ::poll(p, 2, -1);
        if (p[1].revents) return;
        ssize_t n = ::read(pty.master_fd, buf, sizeof buf);
        if (n > 0) got += static_cast<std::size_t>(n);
        while (got >= request_bytes) {
          got -= request_bytes;
          (void)!::write(pty.master_fd, buf, reply_bytes);
        }
      }
    });
  }
  ~EchoServer() {
    (void)!::write(stop[1], "x", 1);
    thread.join();
    ::close(stop[0]);
    ::close(stop[1]);
    close_pty_pair(pty);
  }
};

struct Request {
  const char* name;
  std::vector<Value> values;
};

Request request(int which) {
  switch (which) {
    case 0: return {"GetBatteryLevel", {}};
    case 1: return {"GetOutputState", {std::int64_t{0}}};
    case 2: return {"GetInputValues", {std::int64_t{0}}};
    case 3: return {"PlayTone", {std::int64_t{440}, std::int64_t{10}}};
    default: return {"GetDeviceInfo", {}};
  }
}

double percentile(std::vector<double> us, double q) {
  std::sort(us.begin(), us.end());
  return us[std::min(us.size() - 1, static_cast<std::size_t>(q * static_cast<double>(us.size())))];
}

void percentiles(benchmark::State& state, const std::vector<double>& us) {
  state.counters["p50_us"] = percentile(us, 0.50);
  state.counters["p99_us"] = percentile(us, 0.99);
  state.SetLabel(request(static_cast<int>(state.range(0))).name);
}

double micros_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
}

void BM_PtyRoundTrip(benchmark::State& state) {
  PtyServer server;
  auto port = std::get<std::unique_ptr<Transport>>(open_port({PortKind::Path, server.pty.slave_path}, -1));
  Client client(*port);
  Request r = request(static_cast<int>(state.range(0)));
  const Command& command = *find_command(r.name);
  // The bare round trip moves the same bytes: the framed request and reply.
  const Bytes telegram = std::get<Bytes>(encode_request(command, r.values, true));
  VirtualNxt scratch = make_virtual_nxt();
  const Bytes request_bytes = frame(telegram), reply_bytes = frame(*answer(scratch, telegram));
  EchoServer echo(request_bytes.size(), reply_bytes.size());
  // The echo pty's slave is raw already (open_pty_pair set it).
  int bare_fd = ::open(echo.pty.slave_path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  std::vector<double> us, bare, overhead;
  std::uint8_t buf[512];
  for (auto _ : state) {
    auto t0 = std::chrono::steady_clock::now();
    (void)!::write(bare_fd, request_bytes.data(), request_bytes.size());
    for (std::size_t got = 0; got < reply_bytes.size();) {
      pollfd p{bare_fd, POLLIN, 0};
      ::poll(&p, 1, 1000);
      ssize_t n = ::read(bare_fd, buf, sizeof buf);
      if (n > 0) got += static_cast<std::size_t>(n);
    }
    bare.push_back(micros_since(t0));
    auto t1 = std::chrono::steady_clock::now();
    auto reply = call(client, command, r.values);
    us.push_back(micros_since(t1));
    overhead.push_back(us.back() - bare.back());
    if (!std::holds_alternative<Decoded>(reply)) {
      state.SkipWithError(std::get<CallError>(reply).message.c_str());
      break;
    }
  }
  ::close(bare_fd);
  if (us.empty()) return;
  percentiles(state, us);
  state.counters["bare_p50_us"] = percentile(bare, 0.50);
  state.counters["bare_p99_us"] = percentile(bare, 0.99);
  state.counters["overhead_p50_us"] = percentile(overhead, 0.50);
}
BENCHMARK(BM_PtyRoundTrip)->DenseRange(0, 4)->Iterations(2000)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_InProcess(benchmark::State& state) {
  VirtualNxt brick = make_virtual_nxt();
  InProcessTransport link([&](std::span<const std::uint8_t> t) { return answer(brick, t); });
  Client client(link);
  Request r = request(static_cast<int>(state.range(0)));
  const Command& command = *find_command(r.name);
  std::vector<double> us;
  for (auto _ : state) {
    auto t0 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(call(client, command, r.values));
    us.push_back(micros_since(t0));
  }
  percentiles(state, us);
}
BENCHMARK(BM_InProcess)->DenseRange(0, 4)->Unit(benchmark::kMicrosecond);

// The virtual brick alone: decode the request, act, encode the reply.
void BM_BrickAnswer(benchmark::State& state) {
  VirtualNxt brick = make_virtual_nxt();
  Request r = request(static_cast<int>(state.range(0)));
  const Bytes telegram = std::get<Bytes>(encode_request(*find_command(r.name), r.values, true));
  std::vector<double> us;
  for (auto _ : state) {
    auto t0 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(answer(brick, telegram));
    us.push_back(micros_since(t0));
  }
  percentiles(state, us);
}
BENCHMARK(BM_BrickAnswer)->DenseRange(0, 4)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
