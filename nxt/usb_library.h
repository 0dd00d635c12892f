// libusb-1.0, loaded when a USB port is opened rather than linked into rcxc.
//
// Loading a shared library costs every rcxc start: libusb and the libudev it
// pulls in were a sixth of the CPU that compiling a one-line program took
// (docs/compiler.md, "Compile time"), for a library only `rcxc nxt` over USB
// uses. Loaded here, it costs only that command, and an rcxc on a machine
// without libusb still compiles, runs and talks Bluetooth and ttys; USB then
// says which package is missing. libusb's header still gives the types.
#pragma once

#include <libusb.h>

#include <memory>
#include <string>
#include <variant>

namespace nxt {

// The soname rcxc loads: libusb-1.0's ABI, as Debian's libusb-1.0-0 ships it.
inline constexpr const char* kLibusbSoname = "libusb-1.0.so.0";

// The libusb functions the USB transport calls. Holding one keeps the
// library loaded; the last copy's release unloads it.
struct UsbLibrary {
  std::shared_ptr<void> handle;
  decltype(&libusb_init) init;
  decltype(&libusb_exit) exit;
  decltype(&libusb_strerror) strerror;
  decltype(&libusb_get_device_list) get_device_list;
  decltype(&libusb_free_device_list) free_device_list;
  decltype(&libusb_get_device_descriptor) get_device_descriptor;
  decltype(&libusb_open) open;
  decltype(&libusb_close) close;
  decltype(&libusb_get_string_descriptor_ascii) get_string_descriptor_ascii;
  decltype(&libusb_set_auto_detach_kernel_driver) set_auto_detach_kernel_driver;
  decltype(&libusb_claim_interface) claim_interface;
  decltype(&libusb_release_interface) release_interface;
  decltype(&libusb_bulk_transfer) bulk_transfer;
};

// Loads `soname` and finds every function above in it, or says why not (the
// library is missing, or lacks a function: too old a libusb).
std::variant<UsbLibrary, std::string> load_usb_library(const char* soname = kLibusbSoname);

}  // namespace nxt
