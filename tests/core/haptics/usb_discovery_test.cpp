#include "core/haptics/devices/usb_discovery.h"

#include <gtest/gtest.h>

namespace sulcus {
namespace {

TEST(UsbDiscovery, KnowsTheSupportedDevicesById) {
  EXPECT_EQ(std::string(IdentifyUsb(0x0301, 0x2988)->name),
            "3D Systems (Geomagic) Touch, USB");
  EXPECT_EQ(std::string(IdentifyUsb(0x0403, 0xCB48)->name), "Novint Falcon");
  EXPECT_EQ(std::string(IdentifyUsb(0x1451, 0x0402)->name), "Force Dimension device");
  EXPECT_EQ(std::string(IdentifyUsb(0x256F, 0xC635)->name), "3Dconnexion 3D mouse");
  EXPECT_EQ(std::string(IdentifyUsb(0x046D, 0xC626)->name), "3Dconnexion SpaceNavigator");
  EXPECT_FALSE(IdentifyUsb(0x046D, 0xC52B)) << "a Logitech receiver is not a 3D mouse";
  EXPECT_FALSE(IdentifyUsb(0x0403, 0x6001)) << "an FTDI serial adapter is not a Falcon";
}

TEST(UsbDiscovery, NothingPluggedInIsANormalAnswer) {
  UsbScan scan;
  scan.devices_seen = 3;
  EXPECT_EQ(DescribeScan(scan),
            "No haptic or 6-DoF device is plugged in (3 USB devices seen, none known to "
            "Sulcus). Sulcus runs "
            "without one: the window's mouse and keyboard device, or a scripted or "
            "replayed device.\n");
  scan.usb_available = false;
  scan.error = "No such file or directory";
  EXPECT_EQ(
      DescribeScan(scan).rfind("USB cannot be read here (No such file or directory)", 0),
      0u);
  UsbScan touch;
  touch.known.push_back(
      {0x0301, 0x2988, 1, 4, "3D Systems (Geomagic) Touch, USB", "OpenHaptics"});
  EXPECT_EQ(
      DescribeScan(touch).rfind(
          "3D Systems (Geomagic) Touch, USB (0301:2988, bus 1 device 4): OpenHaptics\n",
          0),
      0u);
}

TEST(UsbDiscovery, ScanningThisMachineDoesNotFail) {
  const UsbScan scan =
      ScanUsb();  // a container may have no USB at all: that is an answer too
  EXPECT_FALSE(DescribeScan(scan).empty());
  if (!scan.usb_available) {
    EXPECT_FALSE(scan.error.empty());
  }
}

}  // namespace
}  // namespace sulcus
