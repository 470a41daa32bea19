#pragma once
// The tactile array over USB (libusb-1.0): asynchronous bulk IN transfers,
// serviced on the thread that calls read() (SensorStream's reader thread).
// The device is chosen by serial number, VID:PID or bus-port, so two
// identical sensors can be told apart. When the cable is pulled, read()
// reports `disconnected` once, then waits for the same device and reports
// `reconnected` when it is back: woken by libusb's hotplug events where the
// platform has them, else polling every 0.5 s (ReconnectPlan says which).
#include <sva/drivers/transport.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sva::drivers {

// Which device: "SERIAL" (its iSerialNumber string), "VID:PID" (hex, e.g.
// "16c0:05dc") or "BUS-PORT[.PORT...]" (e.g. "3-1.2", the physical socket).
struct DeviceSelector {
  std::optional<std::uint16_t> vendor_id, product_id;
  std::string serial;
  int bus = -1;
  std::vector<int> ports;
  static DeviceSelector parse(const std::string& text);  // throws sva::Error on malformed text
  std::string describe() const;
};

struct UsbOptions {
  DeviceSelector device;
  int interface_number = 0;
  std::uint8_t endpoint = 0x81;       // bulk IN
  std::size_t transfer_bytes = 4096;  // per bulk transfer (frames split and merge across them)
  int transfers_in_flight = 4;
  std::chrono::milliseconds reconnect_poll{500};
  bool hotplug = true;  // false: always poll, even where libusb has hotplug events
};

// How a pulled cable's return is noticed.
enum class ReconnectMode { hotplug, polling };
struct ReconnectPlan {
  ReconnectMode mode = ReconnectMode::polling;
  std::string message;  // for status lines: "libusb hotplug events" or "polling every 500 ms (why not hotplug)"
};

// The decision from what libusb offers: hotplug when it is wanted, the platform has it (LIBUSB_CAP_HAS_HOTPLUG)
// and registering the arrival callback returned `register_code` 0; else polling every `poll`, saying why.
ReconnectPlan plan_reconnect(bool wanted, bool platform_has_hotplug, int register_code, std::chrono::milliseconds poll);
// Whether this libusb has hotplug events on this platform (needs no device).
bool usb_has_hotplug();
// The plan a UsbTransport with these options would follow here: registers (and removes) the same arrival callback
// in a libusb context of its own, so it needs no device. Throws sva::Error when USB is unavailable.
ReconnectPlan usb_reconnect_plan(const UsbOptions& options);

struct UsbDeviceInfo {
  std::uint16_t vendor_id = 0, product_id = 0;
  int bus = 0, address = 0;
  std::vector<int> ports;
  std::string serial;  // empty when it cannot be read (permission)
};

// Lists attached USB devices; throws sva::Error when USB is unavailable.
std::vector<UsbDeviceInfo> list_usb_devices();

// The message for a libusb error code while doing `what` to `device`, with the
// likely fix (permission: a udev rule; busy: another program has it).
std::string describe_usb_error(int libusb_code, const std::string& what, const std::string& device);

class UsbTransport : public Transport {
 public:
  // Opens and claims the device; throws sva::Error (USB unavailable, no such
  // device, no permission, not a bulk IN endpoint).
  explicit UsbTransport(UsbOptions options);
  ~UsbTransport() override;
  Chunk read(std::chrono::milliseconds timeout) override;
  void interrupt() override;
  std::string describe() const override;
  const ReconnectPlan& reconnect_plan() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace sva::drivers
