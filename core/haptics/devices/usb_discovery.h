#pragma once
// USB discovery of haptic and 6-DoF input devices (libusb): what is plugged in,
// what it is, and which backend it needs. No device is a normal answer, and so is
// a machine without USB access (a container): both come with a clear message.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sulcus {

struct KnownUsbDevice {
  std::uint16_t vendor = 0;
  int product = -1;  // -1: any product of the vendor
  const char* name = "";
  const char* backend = "";  // what Sulcus needs to use it
};

/// The table of devices Sulcus knows.
const std::vector<KnownUsbDevice>& KnownUsbDevices();
/// The known device with this id, if any.
std::optional<KnownUsbDevice> IdentifyUsb(std::uint16_t vendor, std::uint16_t product);

struct UsbDeviceInfo {
  std::uint16_t vendor = 0, product = 0;
  int bus = 0, address = 0;
  std::string name, backend;
};

struct UsbScan {
  bool usb_available = true;
  std::string error;  // why USB could not be read (when !usb_available)
  int devices_seen = 0;
  std::vector<UsbDeviceInfo> known;
};

/// Lists the known devices plugged in now.
UsbScan ScanUsb();

/// A human answer: what is plugged in and what to do, or that nothing is.
std::string DescribeScan(const UsbScan& scan);

/// Watches for known devices arriving or leaving (libusb hot-plug) on a thread
/// of its own. `supported()` is false where the platform has no hot-plug.
class UsbWatcher {
 public:
  using Callback = std::function<void(bool arrived, const UsbDeviceInfo&)>;
  explicit UsbWatcher(Callback callback);
  ~UsbWatcher();
  bool supported() const;
  const std::string& error() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sulcus
