#pragma once
// The tactile array over USB (libusb-1.0): asynchronous bulk IN transfers,
// serviced on the thread that calls read() (SensorStream's reader thread).
// The device is chosen by serial number, VID:PID or bus-port, so two
// identical sensors can be told apart. When the cable is pulled, read()
// reports `disconnected` once, then polls for the same device and reports
// `reconnected` when it is back.
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
};

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

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace sva::drivers
