#include <sva/drivers/usb_tactile.hpp>
#include <sva/error.hpp>

#include <libusb.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace sva::drivers {

namespace {
constexpr std::uint8_t kMagic0 = 'S', kMagic1 = 'T';
constexpr std::size_t kHeader = 6, kTrailer = 2;

std::string usb_error(int code) { return libusb_error_name(code); }
}  // namespace

std::uint16_t crc16_ccitt(std::span<const std::uint8_t> bytes) {
  std::uint16_t crc = 0xffff;
  for (std::uint8_t b : bytes) {
    crc ^= static_cast<std::uint16_t>(b << 8);
    for (int i = 0; i < 8; ++i) crc = static_cast<std::uint16_t>((crc & 0x8000) ? (crc << 1) ^ 0x1021 : crc << 1);
  }
  return crc;
}

TactileFrame parse_frame(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kHeader + kTrailer)
    throw Error("tactile frame: " + std::to_string(bytes.size()) + " bytes is shorter than a header");
  if (bytes[0] != kMagic0 || bytes[1] != kMagic1) throw Error("tactile frame: bad magic (expected 'ST')");
  TactileFrame f;
  f.rows = bytes[2];
  f.cols = bytes[3];
  f.sequence = static_cast<std::uint16_t>(bytes[4] | (bytes[5] << 8));
  if (f.rows == 0 || f.cols == 0) throw Error("tactile frame: zero rows or columns");
  const std::size_t n = static_cast<std::size_t>(f.rows) * static_cast<std::size_t>(f.cols);
  if (bytes.size() != kHeader + 2 * n + kTrailer)
    throw Error("tactile frame: " + std::to_string(bytes.size()) + " bytes, expected " +
                std::to_string(kHeader + 2 * n + kTrailer) + " for " + std::to_string(f.rows) + " x " +
                std::to_string(f.cols));
  const std::size_t body = kHeader + 2 * n;
  std::uint16_t crc = static_cast<std::uint16_t>(bytes[body] | (bytes[body + 1] << 8));
  if (crc16_ccitt(bytes.first(body)) != crc) throw Error("tactile frame: CRC mismatch (corrupted transfer)");
  f.counts.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    f.counts[i] = static_cast<std::uint16_t>(bytes[kHeader + 2 * i] | (bytes[kHeader + 2 * i + 1] << 8));
  return f;
}

std::vector<std::uint8_t> encode_frame(const TactileFrame& f) {
  std::vector<std::uint8_t> out{kMagic0,
                                kMagic1,
                                static_cast<std::uint8_t>(f.rows),
                                static_cast<std::uint8_t>(f.cols),
                                static_cast<std::uint8_t>(f.sequence & 0xff),
                                static_cast<std::uint8_t>(f.sequence >> 8)};
  for (auto c : f.counts) {
    out.push_back(static_cast<std::uint8_t>(c & 0xff));
    out.push_back(static_cast<std::uint8_t>(c >> 8));
  }
  auto crc = crc16_ccitt(out);
  out.push_back(static_cast<std::uint8_t>(crc & 0xff));
  out.push_back(static_cast<std::uint8_t>(crc >> 8));
  return out;
}

Calibration Calibration::uniform(const SensorSpec& sensor, float gain, float zero) {
  Calibration c;
  c.sensor = sensor;
  c.gain.assign(static_cast<std::size_t>(sensor.elements()), gain);
  c.zero.assign(static_cast<std::size_t>(sensor.elements()), zero);
  return c;
}

Calibration Calibration::load(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw Error(file.string() + ": cannot read calibration file");
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw Error(file.string() + ": invalid JSON: " + e.what());
  }
  auto fail = [&](const std::string& what) -> Error { return Error(file.string() + ": " + what); };
  if (!j.is_object()) throw fail("expected a JSON object");
  Calibration c;
  try {
    c.sensor.rows = j.at("rows").get<int>();
    c.sensor.cols = j.at("cols").get<int>();
    c.sensor.pitch_mm = j.at("pitch_mm").get<double>();
    c.gain = j.at("gain_kpa_per_count").get<std::vector<float>>();
    c.zero = j.at("zero_counts").get<std::vector<float>>();
  } catch (const nlohmann::json::exception& e) {
    throw fail(std::string("missing or mistyped field: ") + e.what());
  }
  if (c.sensor.rows < 1 || c.sensor.cols < 1 || c.sensor.rows > 255 || c.sensor.cols > 255)
    throw fail("rows/cols must be in [1, 255]");
  if (!(c.sensor.pitch_mm > 0) || !std::isfinite(c.sensor.pitch_mm)) throw fail("pitch_mm must be positive");
  const auto n = static_cast<std::size_t>(c.sensor.elements());
  if (c.gain.size() != n || c.zero.size() != n)
    throw fail("gain_kpa_per_count and zero_counts need rows*cols values each");
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(c.gain[i]) || !std::isfinite(c.zero[i]) || c.gain[i] < 0)
      throw fail("non-finite or negative calibration value at element " + std::to_string(i));
  return c;
}

std::vector<float> Calibration::to_pressure(const TactileFrame& f) const {
  if (f.rows != sensor.rows || f.cols != sensor.cols)
    throw Error("tactile frame is " + std::to_string(f.rows) + " x " + std::to_string(f.cols) +
                ", the calibration is for " + std::to_string(sensor.rows) + " x " + std::to_string(sensor.cols));
  std::vector<float> p(f.counts.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    p[i] = std::max(0.0f, gain[i] * (static_cast<float>(f.counts[i]) - zero[i]));
  return p;
}

std::vector<UsbDeviceInfo> list_usb_devices() {
  libusb_context* ctx = nullptr;
  if (int r = libusb_init(&ctx); r != 0) throw Error("USB unavailable: libusb_init failed (" + usb_error(r) + ")");
  libusb_device** list = nullptr;
  ssize_t n = libusb_get_device_list(ctx, &list);
  std::vector<UsbDeviceInfo> out;
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
    out.push_back({d.idVendor, d.idProduct, libusb_get_bus_number(list[i]), libusb_get_device_address(list[i])});
  }
  if (list) libusb_free_device_list(list, 1);
  libusb_exit(ctx);
  if (n < 0) throw Error("USB unavailable: cannot list devices (" + usb_error(static_cast<int>(n)) + ")");
  return out;
}

struct UsbTactileSensor::Impl {
  libusb_context* ctx = nullptr;
  libusb_device_handle* handle = nullptr;
  UsbSensorOptions options;
  bool claimed = false;
  ~Impl() {
    if (claimed) libusb_release_interface(handle, options.interface_number);
    if (handle) libusb_close(handle);
    if (ctx) libusb_exit(ctx);
  }
};

UsbTactileSensor::UsbTactileSensor(const UsbSensorOptions& options, Calibration calibration)
    : impl_(std::make_unique<Impl>()), calibration_(std::move(calibration)) {
  impl_->options = options;
  if (int r = libusb_init(&impl_->ctx); r != 0)
    throw Error("USB unavailable: libusb_init failed (" + usb_error(r) + ")");
  impl_->handle = libusb_open_device_with_vid_pid(impl_->ctx, options.vendor_id, options.product_id);
  if (!impl_->handle) {
    char id[16];
    std::snprintf(id, sizeof id, "%04x:%04x", options.vendor_id, options.product_id);
    throw Error(std::string("no tactile sensor ") + id +
                " found (is it plugged in, and do you have permission to open it?)");
  }
  libusb_set_auto_detach_kernel_driver(impl_->handle, 1);
  if (int r = libusb_claim_interface(impl_->handle, options.interface_number); r != 0)
    throw Error("cannot claim USB interface " + std::to_string(options.interface_number) + " (" + usb_error(r) + ")");
  impl_->claimed = true;
}

UsbTactileSensor::~UsbTactileSensor() = default;

std::vector<float> UsbTactileSensor::read_pressure() {
  const std::size_t n = static_cast<std::size_t>(calibration_.sensor.elements());
  std::vector<std::uint8_t> buf(kHeader + 2 * n + kTrailer);
  int got = 0;
  int r = libusb_bulk_transfer(impl_->handle, impl_->options.endpoint, buf.data(), static_cast<int>(buf.size()), &got,
                               impl_->options.timeout_ms);
  if (r == LIBUSB_ERROR_TIMEOUT)
    throw Error("tactile sensor: no frame within " + std::to_string(impl_->options.timeout_ms) + " ms");
  if (r != 0) throw Error("tactile sensor: bulk transfer failed (" + usb_error(r) + ")");
  buf.resize(static_cast<std::size_t>(got));
  return calibration_.to_pressure(parse_frame(buf));
}

}  // namespace sva::drivers
