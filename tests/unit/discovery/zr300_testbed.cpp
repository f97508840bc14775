#include "zr300_testbed.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string_view>

namespace vifusion::discovery::test {
namespace {

constexpr const char* kHostControllerDevpath = "/devices/pci0000:00/0000:00:14.0";
constexpr int kUsbDeviceMajor = 189;  // Linux usb_device character major
constexpr int kVideoMajor = 81;       // Linux video4linux character major

// One UVC function of the DS4: its VideoControl interface number and the stream it carries. Listed (and
// numbered /dev/video*) colour first, so that only bInterfaceNumber can order them right.
struct CameraFunction {
  int interface_number;
  int stream;  // 0 IR, 1 depth, 2 colour
};
constexpr CameraFunction kCameraFunctions[] = {{4, 2}, {0, 0}, {2, 1}};

std::string threeDigits(int value) {
  char text[16];
  std::snprintf(text, sizeof(text), "%03d", value);
  return text;
}

std::string twoHexDigits(int value) {
  char text[16];
  std::snprintf(text, sizeof(text), "%02x", value);
  return text;
}

std::string sysPath(const std::string& devpath) { return "/sys" + devpath; }

struct UsbDeviceText {
  std::string devpath;
  int bus = 0;
  int devnum = 0;
  const char* vendor_id = "";
  const char* product_id = "";
  const char* product_variable = "";  // PRODUCT=vendor/product/bcdDevice, hex without leading zeros
  const char* manufacturer = "";
  const char* product = "";
  std::string serial;
};

std::string usbDeviceDescription(const UsbDeviceText& device) {
  const std::string node = "bus/usb/" + threeDigits(device.bus) + "/" + threeDigits(device.devnum);
  const int minor = (device.bus - 1) * 128 + device.devnum - 1;
  std::string text = "P: " + device.devpath + "\nN: " + node + "\nE: DEVNAME=/dev/" + node +
                     "\nE: DEVTYPE=usb_device\nE: DRIVER=usb\nE: SUBSYSTEM=usb\nE: PRODUCT=" + device.product_variable +
                     "\nE: BUSNUM=" + threeDigits(device.bus) + "\nE: DEVNUM=" + threeDigits(device.devnum) +
                     "\nE: MAJOR=" + std::to_string(kUsbDeviceMajor) + "\nE: MINOR=" + std::to_string(minor) +
                     "\nA: idVendor=" + device.vendor_id + "\nA: idProduct=" + device.product_id +
                     "\nA: busnum=" + std::to_string(device.bus) + "\nA: devnum=" + std::to_string(device.devnum) +
                     "\nA: manufacturer=" + device.manufacturer + "\nA: product=" + device.product + "\n";
  if (!device.serial.empty()) text += "A: serial=" + device.serial + "\nE: ID_SERIAL_SHORT=" + device.serial + "\n";
  return text;
}

std::string interfaceDescription(const std::string& devpath, int number, const char* interface_class,
                                 const char* interface_subclass) {
  return "P: " + devpath + "\nE: DEVTYPE=usb_interface\nE: SUBSYSTEM=usb\nA: bInterfaceNumber=" + twoHexDigits(number) +
         "\nA: bInterfaceClass=" + interface_class + "\nA: bInterfaceSubClass=" + interface_subclass + "\n";
}

constexpr const char* kVideoClass = "0e";
constexpr const char* kVideoControlSubclass = "01";
constexpr const char* kVideoStreamingSubclass = "02";
constexpr const char* kVendorClass = "ff";

}  // namespace

bool umockdevPreloaded() {
  const char* preload = std::getenv("LD_PRELOAD");
  return preload != nullptr && std::string_view(preload).find("libumockdev-preload") != std::string_view::npos;
}

Zr300Testbed::Zr300Testbed() : testbed_(umockdev_testbed_new()) {}

Zr300Testbed::~Zr300Testbed() { g_object_unref(testbed_); }  // removes the test bed's directory

std::string Zr300Testbed::rootDir() const {
  gchar* root = umockdev_testbed_get_root_dir(testbed_);
  std::string path(root);
  g_free(root);
  return path;
}

void Zr300Testbed::addFromString(const std::string& description) {
  GError* error = nullptr;
  if (!umockdev_testbed_add_from_string(testbed_, description.c_str(), &error)) {
    const std::string message = error != nullptr ? error->message : "unknown error";
    g_clear_error(&error);
    throw std::runtime_error("umockdev_testbed_add_from_string: " + message + "\n" + description);
  }
  if (event_listener_) event_listener_();
}

std::string Zr300Testbed::addVideoNode(const std::string& interface_devpath, int index, bool capture) {
  const int number = next_video_number_++;
  const std::string name = "video" + std::to_string(number);
  const std::string devpath = interface_devpath + "/video4linux/" + name;
  // v4l_id (udev) writes the capabilities; a metadata node has neither capture nor output.
  addFromString("P: " + devpath + "\nN: " + name + "\nE: DEVNAME=/dev/" + name +
                "\nE: SUBSYSTEM=video4linux\nE: MAJOR=" + std::to_string(kVideoMajor) +
                "\nE: MINOR=" + std::to_string(number) + "\nE: ID_V4L_CAPABILITIES=" + (capture ? ":capture:" : ":") +
                "\nA: index=" + std::to_string(index) + "\nA: name=Intel RealSense\n");
  return devpath;
}

FakeZr300Paths Zr300Testbed::add(const FakeZr300& device) {
  FakeZr300Paths paths;
  const std::string port = std::to_string(device.bus) + "-" + std::to_string(device.hub_port);
  const std::string hub_devpath =
      std::string(kHostControllerDevpath) + "/usb" + std::to_string(device.bus) + "/" + port;
  addFromString(
      usbDeviceDescription({hub_devpath, device.bus, next_usb_devnum_++, "0451", "8025", "451/8025/100", "", "", ""}));
  paths.hub = sysPath(hub_devpath);

  if (device.camera_present) {
    const std::string camera_devpath = hub_devpath + "/" + port + ".1";
    const int devnum = next_usb_devnum_++;
    addFromString(usbDeviceDescription({camera_devpath, device.bus, devnum, "8086", "0acb", "8086/acb/247c",
                                        "Intel Corp", "Intel RealSense 3D Camera ZR300", device.serial}));
    paths.camera = sysPath(camera_devpath);
    paths.camera_usb_devnode = "/dev/bus/usb/" + threeDigits(device.bus) + "/" + threeDigits(devnum);
    int bound = 0;
    for (const CameraFunction& function : kCameraFunctions) {
      const std::string control = camera_devpath + "/" + port + ".1:1." + std::to_string(function.interface_number);
      const std::string streaming =
          camera_devpath + "/" + port + ".1:1." + std::to_string(function.interface_number + 1);
      addFromString(interfaceDescription(control, function.interface_number, kVideoClass, kVideoControlSubclass));
      addFromString(
          interfaceDescription(streaming, function.interface_number + 1, kVideoClass, kVideoStreamingSubclass));
      paths.interfaces.push_back(sysPath(control));
      paths.interfaces.push_back(sysPath(streaming));
      if (bound++ >= device.bound_camera_functions) continue;
      // uvcvideo registers the capture node (index 0), then the metadata node (index 1).
      const std::string capture = addVideoNode(control, 0, true);
      paths.camera_video_nodes.push_back(sysPath(capture));
      paths.stream_devnodes[function.stream] = "/dev/" + capture.substr(capture.rfind('/') + 1);
      if (device.metadata_nodes) paths.camera_video_nodes.push_back(sysPath(addVideoNode(control, 1, false)));
    }
  }

  if (device.adapter) {
    const std::string adapter_devpath = hub_devpath + "/" + port + ".2";
    const int devnum = next_usb_devnum_++;
    addFromString(usbDeviceDescription(
        {adapter_devpath, device.bus, devnum, "8086", "0ad0", "8086/ad0/0", "Cypress", "CX3-UVC", ""}));
    paths.adapter = sysPath(adapter_devpath);
    paths.adapter_usb_devnode = "/dev/bus/usb/" + threeDigits(device.bus) + "/" + threeDigits(devnum);
    const std::string control = adapter_devpath + "/" + port + ".2:1.0";
    addFromString(interfaceDescription(control, 0, kVideoClass, kVideoControlSubclass));
    addFromString(
        interfaceDescription(adapter_devpath + "/" + port + ".2:1.1", 1, kVideoClass, kVideoStreamingSubclass));
    addFromString(interfaceDescription(adapter_devpath + "/" + port + ".2:1.2", 2, kVendorClass, "00"));
    for (int number = 0; number < 3; ++number) {
      paths.interfaces.push_back(sysPath(adapter_devpath + "/" + port + ".2:1." + std::to_string(number)));
    }
    if (device.adapter_video_nodes) {
      const std::string fisheye = addVideoNode(control, 0, true);
      paths.adapter_video_nodes.push_back(sysPath(fisheye));
      paths.fisheye_devnode = "/dev/" + fisheye.substr(fisheye.rfind('/') + 1);
      if (device.metadata_nodes) paths.adapter_video_nodes.push_back(sysPath(addVideoNode(control, 1, false)));
    }
  }
  return paths;
}

std::string Zr300Testbed::addOtherUsbCamera(int bus, int hub_port, const char* vendor_id, const char* product_id) {
  const std::string port = std::to_string(bus) + "-" + std::to_string(hub_port);
  const std::string devpath = std::string(kHostControllerDevpath) + "/usb" + std::to_string(bus) + "/" + port;
  const std::string product_variable = std::string(vendor_id) + "/" + product_id + "/1";
  addFromString(usbDeviceDescription({devpath, bus, next_usb_devnum_++, vendor_id, product_id, product_variable.c_str(),
                                      "Other", "Other camera", "OTHER1"}));
  const std::string control = devpath + "/" + port + ":1.0";
  addFromString(interfaceDescription(control, 0, kVideoClass, kVideoControlSubclass));
  addVideoNode(control, 0, true);
  return sysPath(devpath);
}

void Zr300Testbed::uevent(const std::string& syspath, const char* action) {
  umockdev_testbed_uevent(testbed_, syspath.c_str(), action);
  if (event_listener_) event_listener_();
}

void Zr300Testbed::unplug(const FakeZr300Paths& paths) {
  // One by one, so that umockdev also drops each device's /sys/class and /sys/bus links (removing the hub
  // alone would leave them, and the same camera could not be added again).
  std::vector<std::string> gone;
  auto removeDevice = [&](const std::string& device, const std::vector<std::string>& video_nodes) {
    if (device.empty()) return;
    for (const std::string& node : video_nodes) {
      uevent(node, "remove");
      gone.push_back(node);
    }
    for (const std::string& interface : paths.interfaces) {
      if (!interface.starts_with(device + "/")) continue;
      uevent(interface, "remove");
      gone.push_back(interface);
    }
    uevent(device, "remove");
    gone.push_back(device);
  };
  removeDevice(paths.camera, paths.camera_video_nodes);
  removeDevice(paths.adapter, paths.adapter_video_nodes);
  uevent(paths.hub, "remove");
  gone.push_back(paths.hub);
  for (const std::string& device : gone) umockdev_testbed_remove_device(testbed_, device.c_str());
}

}  // namespace vifusion::discovery::test
