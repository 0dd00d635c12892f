// NXT round trips over a pseudo-terminal: the host client on the slave, the
// virtual NXT served on the master in a thread, as `rcxc nxt brick --pty`
// does. What is measured is the host's whole overhead per command (encode,
// frame, pty both ways, the virtual brick, decode): a real brick adds its
// own link time (about 60 ms per reply on Bluetooth, a few ms on USB).
// Counters p50_us and p99_us are per-round-trip percentiles; the goal is
// p99 under 1 ms. BM_InProcess is the same without the pty.
#include <benchmark/benchmark.h>
#include <unistd.h>

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

void percentiles(benchmark::State& state, std::vector<double>& us) {
  std::sort(us.begin(), us.end());
  auto at = [&](double q) { return us[std::min(us.size() - 1, static_cast<std::size_t>(q * static_cast<double>(us.size())))]; };
  state.counters["p50_us"] = at(0.50);
  state.counters["p99_us"] = at(0.99);
  state.SetLabel(request(static_cast<int>(state.range(0))).name);
}

void BM_PtyRoundTrip(benchmark::State& state) {
  PtyServer server;
  auto port = std::get<std::unique_ptr<Transport>>(open_port({PortKind::Path, server.pty.slave_path}, -1));
  Client client(*port);
  Request r = request(static_cast<int>(state.range(0)));
  const Command& command = *find_command(r.name);
  std::vector<double> us;
  for (auto _ : state) {
    auto t0 = std::chrono::steady_clock::now();
    auto reply = call(client, command, r.values);
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
    if (!std::holds_alternative<Decoded>(reply)) {
      state.SkipWithError(std::get<CallError>(reply).message.c_str());
      return;
    }
  }
  percentiles(state, us);
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
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
  }
  percentiles(state, us);
}
BENCHMARK(BM_InProcess)->DenseRange(0, 4)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
