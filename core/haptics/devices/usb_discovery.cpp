#include "core/haptics/devices/usb_discovery.h"

#include <libusb-1.0/libusb.h>

#include <atomic>
#include <cstdio>
#include <thread>

namespace sulcus {
namespace {

constexpr const char* kSpaceMouseBackend =
    "6-DoF input without force feedback; Sulcus has no 3D-mouse backend yet, use the "
    "mouse and keyboard";

UsbDeviceInfo Info(libusb_device* dev, const libusb_device_descriptor& d,
                   const KnownUsbDevice& k) {
  UsbDeviceInfo info;
  info.vendor = d.idVendor;
  info.product = d.idProduct;
  info.bus = libusb_get_bus_number(dev);
  info.address = libusb_get_device_address(dev);
  info.name = k.name;
  info.backend = k.backend;
  return info;
}

std::string Hex4(unsigned v) {
  char s[8];
  std::snprintf(s, sizeof s, "%04x", v);
  return s;
}

}  // namespace

const std::vector<KnownUsbDevice>& KnownUsbDevices() {
  static const std::vector<KnownUsbDevice> known = {
      {0x0301, 0x2988, "3D Systems (Geomagic) Touch, USB",
       "OpenHaptics (build Sulcus with the OpenHaptics SDK and the Touch device driver "
       "installed)"},
      {0x0403, 0xCB48, "Novint Falcon",
       "no Sulcus backend (3-DoF; would need libnifalcon)"},
      {0x1451, -1, "Force Dimension device",
       "no Sulcus backend (would need the Force Dimension SDK)"},
      // 3Dconnexion under Logitech's vendor id: only its known 3D mice (0x046D is
      // Logitech's id).
      {0x046D, 0xC603, "3Dconnexion SpaceMouse Plus XT", kSpaceMouseBackend},
      {0x046D, 0xC605, "3Dconnexion CadMan", kSpaceMouseBackend},
      {0x046D, 0xC606, "3Dconnexion SpaceMouse Classic", kSpaceMouseBackend},
      {0x046D, 0xC621, "3Dconnexion SpaceBall 5000", kSpaceMouseBackend},
      {0x046D, 0xC623, "3Dconnexion SpaceTraveler", kSpaceMouseBackend},
      {0x046D, 0xC625, "3Dconnexion SpacePilot", kSpaceMouseBackend},
      {0x046D, 0xC626, "3Dconnexion SpaceNavigator", kSpaceMouseBackend},
      {0x046D, 0xC627, "3Dconnexion SpaceExplorer", kSpaceMouseBackend},
      {0x046D, 0xC628, "3Dconnexion SpaceNavigator for Notebooks", kSpaceMouseBackend},
      {0x046D, 0xC629, "3Dconnexion SpacePilot Pro", kSpaceMouseBackend},
      {0x046D, 0xC62B, "3Dconnexion SpaceMouse Pro", kSpaceMouseBackend},
      {0x256F, -1, "3Dconnexion 3D mouse", kSpaceMouseBackend},
  };
  return known;
}

std::optional<KnownUsbDevice> IdentifyUsb(std::uint16_t vendor, std::uint16_t product) {
  for (const KnownUsbDevice& k : KnownUsbDevices())
    if (k.vendor == vendor && (k.product < 0 || k.product == product)) return k;
  return std::nullopt;
}

UsbScan ScanUsb() {
  UsbScan scan;
  libusb_context* ctx = nullptr;
  if (const int err = libusb_init(&ctx); err != 0) {
    scan.usb_available = false;
    scan.error = libusb_strerror(static_cast<libusb_error>(err));
    return scan;
  }
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(ctx, &list);
  if (n < 0) {
    scan.usb_available = false;
    scan.error = libusb_strerror(static_cast<libusb_error>(n));
  } else {
    scan.devices_seen = static_cast<int>(n);
    for (ssize_t i = 0; i < n; ++i) {
      libusb_device_descriptor d{};
      if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
      if (const auto k = IdentifyUsb(d.idVendor, d.idProduct))
        scan.known.push_back(Info(list[i], d, *k));
    }
    libusb_free_device_list(list, 1);
  }
  libusb_exit(ctx);
  return scan;
}

std::string DescribeScan(const UsbScan& scan) {
  std::string out;
  if (!scan.usb_available) {
    out += "USB cannot be read here (" + scan.error +
           "), so no haptic device can be found. Sulcus runs without one: the window's "
           "mouse and "
           "keyboard device, or a scripted or replayed device.\n";
    return out;
  }
  if (scan.known.empty()) {
    out += "No haptic or 6-DoF device is plugged in (" +
           std::to_string(scan.devices_seen) +
           " USB devices seen, none known to Sulcus). Sulcus runs without one: the "
           "window's mouse and keyboard "
           "device, or a scripted or replayed device.\n";
    return out;
  }
  for (const UsbDeviceInfo& d : scan.known)
    out += d.name + " (" + Hex4(d.vendor) + ":" + Hex4(d.product) + ", bus " +
           std::to_string(d.bus) + " device " + std::to_string(d.address) +
           "): " + d.backend + "\n";
  out +=
      "If a device is listed but cannot be opened, install "
      "resources/udev/70-sulcus-haptics.rules (see its header).\n";
  return out;
}

struct UsbWatcher::Impl {
  libusb_context* ctx = nullptr;
  libusb_hotplug_callback_handle handle = 0;
  bool supported = false;
  std::string error;
  Callback callback;
  std::atomic<bool> stop{false};
  std::thread events;

  static int LIBUSB_CALL OnHotplug(libusb_context*, libusb_device* dev,
                                   libusb_hotplug_event event, void* self) {
    auto* impl = static_cast<Impl*>(self);
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(dev, &d) != 0) return 0;
    if (const auto k = IdentifyUsb(d.idVendor, d.idProduct))
      impl->callback(event == LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED, Info(dev, d, *k));
    return 0;  // stay registered
  }
};

UsbWatcher::UsbWatcher(Callback callback) : impl_(std::make_unique<Impl>()) {
  impl_->callback = std::move(callback);
  if (const int err = libusb_init(&impl_->ctx); err != 0) {
    impl_->error = libusb_strerror(static_cast<libusb_error>(err));
    impl_->ctx = nullptr;
    return;
  }
  if (!libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG)) {
    impl_->error = "this platform's libusb has no hot-plug support";
    return;
  }
  const int err = libusb_hotplug_register_callback(
      impl_->ctx,
      static_cast<libusb_hotplug_event>(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED |
                                        LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT),
      LIBUSB_HOTPLUG_ENUMERATE, LIBUSB_HOTPLUG_MATCH_ANY, LIBUSB_HOTPLUG_MATCH_ANY,
      LIBUSB_HOTPLUG_MATCH_ANY, &Impl::OnHotplug, impl_.get(), &impl_->handle);
  if (err != LIBUSB_SUCCESS) {
    impl_->error = libusb_strerror(static_cast<libusb_error>(err));
    return;
  }
  impl_->supported = true;
  impl_->events = std::thread([impl = impl_.get()] {
    while (!impl->stop.load()) {
      timeval tv{0, 100000};
      libusb_handle_events_timeout_completed(impl->ctx, &tv, nullptr);
    }
  });
}

UsbWatcher::~UsbWatcher() {
  impl_->stop = true;
  if (impl_->supported) libusb_hotplug_deregister_callback(impl_->ctx, impl_->handle);
  if (impl_->events.joinable()) impl_->events.join();
  if (impl_->ctx) libusb_exit(impl_->ctx);
}

bool UsbWatcher::supported() const { return impl_->supported; }
const std::string& UsbWatcher::error() const { return impl_->error; }

}  // namespace sulcus
