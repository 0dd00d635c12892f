#include "nxt/usb_library.h"

#include <dlfcn.h>

#include <fmt/format.h>

namespace nxt {
namespace {

// Finds `name` in the library and stores it in `slot`; false when absent.
template <typename Function>
bool find(void* library, const char* name, Function& slot) {
  void* symbol = ::dlsym(library, name);
  slot = reinterpret_cast<Function>(symbol);
  return symbol != nullptr;
}

}  // namespace

std::variant<UsbLibrary, std::string> load_usb_library(const char* soname) {
  // RTLD_LOCAL: libusb's names stay out of the way of anything loaded later.
  void* library = ::dlopen(soname, RTLD_NOW | RTLD_LOCAL);
  if (!library) {
    const char* why = ::dlerror();
    return fmt::format("cannot load {} ({}): USB needs libusb-1.0 (Debian and Ubuntu: apt-get install libusb-1.0-0)",
                       soname, why ? why : "not found");
  }
  UsbLibrary usb{};
  usb.handle = std::shared_ptr<void>(library, [](void* l) { ::dlclose(l); });
  const char* missing = nullptr;
  auto need = [&](const char* name, auto& slot) {
    if (!missing && !find(library, name, slot)) missing = name;
  };
  need("libusb_init", usb.init);
  need("libusb_exit", usb.exit);
  need("libusb_strerror", usb.strerror);
  need("libusb_get_device_list", usb.get_device_list);
  need("libusb_free_device_list", usb.free_device_list);
  need("libusb_get_device_descriptor", usb.get_device_descriptor);
  need("libusb_open", usb.open);
  need("libusb_close", usb.close);
  need("libusb_get_string_descriptor_ascii", usb.get_string_descriptor_ascii);
  need("libusb_set_auto_detach_kernel_driver", usb.set_auto_detach_kernel_driver);
  need("libusb_claim_interface", usb.claim_interface);
  need("libusb_release_interface", usb.release_interface);
  need("libusb_bulk_transfer", usb.bulk_transfer);
  if (missing) return fmt::format("{} has no {}: USB needs libusb-1.0.16 or later", soname, missing);
  return usb;
}

}  // namespace nxt
