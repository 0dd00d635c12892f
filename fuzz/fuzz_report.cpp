// Bytes as a .rcx file, run bounded, then every report writer: the text
// timeline (whose symbol names must come out without control characters),
// the JSON report and trace (written event by event as `rcxc run` writes
// them, which must be the trees' dump with invalid UTF-8 replaced), the VCD
// trace, and the SVG drawing (whose text must stay
// ASCII without `<` or `&` outside markup: names are escaped).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <sstream>
#include <variant>

#include "rcx/image.h"
#include "runtime/report.h"
#include "runtime/trace_svg.h"
#include "runtime/vm.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto result = rcx::read_image(std::span<const std::uint8_t>(data, size));
  const auto* image = std::get_if<rcx::Image>(&result);
  if (image == nullptr) return 0;
  rcx::Machine machine;
  if (machine.load(0, *image)) return 0;
  machine.start_program();
  machine.run(500 * 1000);
  std::string text = rcx::timeline_text(machine, *image);
  for (char c : text)
    if (static_cast<unsigned char>(c) < 0x20 && c != '\n') std::abort();  // a name was not escaped
  auto dumped = [](const nlohmann::json& j) { return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace); };
  std::ostringstream report, trace;
  rcx::write_report_json(report, machine, *image);
  rcx::write_trace_json(trace, machine, *image);
  if (report.str() != dumped(rcx::report_json(machine, *image))) std::abort();
  if (trace.str() != dumped(rcx::trace_json(machine, *image))) std::abort();
  (void)rcx::trace_vcd(machine, *image);
  std::string svg = rcx::trace_svg(machine, *image, {}, "fuzz");
  for (char c : svg)
    if (static_cast<unsigned char>(c) >= 0x80 || (static_cast<unsigned char>(c) < 0x20 && c != '\n')) std::abort();
  return 0;
}
