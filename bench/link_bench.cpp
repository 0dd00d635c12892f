// IR link download speed.
//
// BM_DownloadPaced: rcxc's downloader into the virtual brick on a pty that
// answers at 2400 baud (as `rcxc brick --pty` does), in real time.
// BM_NqcDownloadPaced: nqc's download of the same image into the same kind
// of brick (skipped when nqc is not installed).
// BM_DownloadVirtual: the same download in memory, in virtual time; the
// counter `link_s` is what it would take on a 2400-baud line, with noise.
// Counters: `floor_s` is the wire floor, 2 x bytes x 11 bits / 2400 for the
// program bytes plus the framing of the requests and replies a download
// cannot avoid; `vs_floor` is the measured time over that floor.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <thread>

#include "link/brick_server.h"
#include "link/download.h"

namespace {

using namespace rcx;

Image program(std::size_t bytes) {
  Image image;
  Fragment main{FragmentType::Task, 0, {}};
  while (main.code.size() + 5 <= bytes) {
    Bytes cmd{0x14, 0x01, 0x02, static_cast<std::uint8_t>(main.code.size()), 0x00};  // set var 1
    main.code.insert(main.code.end(), cmd.begin(), cmd.end());
  }
  image.fragments.push_back(main);
  return image;
}

// Framing of a message with `payload` bytes: header, doubled bytes, checksum pair.
double message_bytes(double payload) { return 3 + 2 * payload + 2; }

// The least a download of `bytes` (one task) can cost at 2400 baud: the
// framed requests and replies a download cannot do without (Alive, Stop all
// tasks, Set program number, Delete all tasks and subroutines, Start task
// download, the Transfer data blocks of at most 64 bytes, the download-done
// sound), every byte sent twice (value and complement) at 11 bits. A serial
// tower's echo overlaps the sending, so it adds nothing.
double floor_seconds(std::size_t bytes) {
  const double blocks = std::ceil(static_cast<double>(bytes) / 64.0);
  // request payload, reply payload
  double wire = message_bytes(1) + message_bytes(1)     // alive
                + message_bytes(1) + message_bytes(1)   // stop all tasks
                + message_bytes(2) + message_bytes(1)   // set program number
                + 2 * (message_bytes(1) + message_bytes(1))  // delete all tasks, subroutines
                + message_bytes(6) + message_bytes(2)   // start task download
                + message_bytes(2) + message_bytes(1);  // play sound
  wire += blocks * (message_bytes(6) + message_bytes(2)) + 2 * static_cast<double>(bytes);
  return wire * kByteSeconds;
}

struct PacedBrick {
  Brick brick = make_brick();
  Pty pty;
  int stop[2] = {-1, -1};
  std::thread server;
  PacedBrick() {
    pty = std::move(std::get<Pty>(open_pty()));
    if (::pipe(stop) != 0) std::abort();
    ServeOptions options;
    options.stop_fd = stop[0];
    server = std::thread([this, options] { serve(brick, *pty.master, options); });
  }
  ~PacedBrick() {
    (void)!::write(stop[1], "x", 1);
    server.join();
    ::close(stop[0]);
    ::close(stop[1]);
    close_pty(pty);
  }
};

void report(benchmark::State& state, std::size_t bytes, double seconds) {
  state.counters["bytes"] = static_cast<double>(bytes);
  state.counters["floor_s"] = floor_seconds(bytes);
  state.counters["link_s"] = seconds;
  state.counters["vs_floor"] = seconds / floor_seconds(bytes);
}

void BM_DownloadPaced(benchmark::State& state) {
  const auto size = static_cast<std::size_t>(state.range(0));
  Image image = program(size);
  PacedBrick brick;
  auto port = std::move(std::get<std::unique_ptr<Transport>>(open_port({brick.pty.slave_path, PortKind::Serial})));
  double total = 0;
  for (auto _ : state) {
    Link link = make_link(*port);
    auto t0 = std::chrono::steady_clock::now();
    auto r = download(link, image, {});
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!std::holds_alternative<DownloadReport>(r)) state.SkipWithError("download failed");
    state.SetIterationTime(s);
    total += s;
  }
  report(state, image.fragments[0].code.size(), total / static_cast<double>(state.iterations()));
}
BENCHMARK(BM_DownloadPaced)->Arg(100)->Arg(400)->Iterations(2)->UseManualTime()->Unit(benchmark::kMillisecond);

void BM_NqcDownloadPaced(benchmark::State& state) {
  if (::access("/usr/bin/nqc", X_OK) != 0) {
    state.SkipWithError("nqc is not installed");
    for (auto _ : state) {
    }
    return;
  }
  const auto size = static_cast<std::size_t>(state.range(0));
  Image image = program(size);
  std::string path = "/tmp/rcxc_link_bench.rcx";
  auto bytes = write_image(image);
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                               static_cast<std::streamsize>(bytes.size()));
  PacedBrick brick;
  std::string cmd = "/usr/bin/nqc -S" + brick.pty.slave_path + " -d " + path + " >/dev/null 2>&1";
  double total = 0;
  for (auto _ : state) {
    auto t0 = std::chrono::steady_clock::now();
    int rc = std::system(cmd.c_str());
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (rc != 0) state.SkipWithError("nqc download failed");
    state.SetIterationTime(s);
    total += s;
  }
  report(state, image.fragments[0].code.size(), total / static_cast<double>(state.iterations()));
}
BENCHMARK(BM_NqcDownloadPaced)->Arg(100)->Arg(400)->Iterations(2)->UseManualTime()->Unit(benchmark::kMillisecond);

// In memory: CPU cost of the protocol, and the virtual 2400-baud time with
// `noise` percent of the bytes lost or corrupted.
void BM_DownloadVirtual(benchmark::State& state) {
  const auto size = static_cast<std::size_t>(state.range(0));
  const double noise = static_cast<double>(state.range(1)) / 100.0;
  Image image = program(size);
  double link_seconds = 0;
  int ok = 0, runs = 0;
  for (auto _ : state) {
    Brick brick = make_brick();
    BrickWire wire(brick, noise, static_cast<std::uint64_t>(runs) + 1, true);
    Link link = make_link(wire);
    auto r = download(link, image, {});
    ok += std::holds_alternative<DownloadReport>(r);
    ++runs;
    link_seconds += static_cast<double>(wire.elapsed()) / 1e6;
  }
  report(state, image.fragments[0].code.size(), link_seconds / runs);
  state.counters["success"] = static_cast<double>(ok) / runs;
}
BENCHMARK(BM_DownloadVirtual)->Args({100, 0})->Args({400, 0})->Args({400, 1})->Args({400, 5});

}  // namespace

BENCHMARK_MAIN();
