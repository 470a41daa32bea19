#include <sva/drivers/usb_transport.hpp>
#include <sva/error.hpp>

#include <libusb.h>

#include <atomic>
#include <charconv>
#include <cstdio>
#include <deque>
#include <thread>

namespace sva::drivers {

namespace {

std::optional<long> parse_number(const std::string& s, int base) {
  long v = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v, base);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

std::string hex4(std::uint16_t v) {
  char b[8];
  std::snprintf(b, sizeof b, "%04x", v);
  return b;
}

std::vector<int> port_path(libusb_device* dev) {
  std::uint8_t ports[8];
  int n = libusb_get_port_numbers(dev, ports, 8);
  return n > 0 ? std::vector<int>(ports, ports + n) : std::vector<int>{};
}

std::string read_serial(libusb_device_handle* h, const libusb_device_descriptor& d) {
  if (!d.iSerialNumber) return {};
  unsigned char buf[256];
  int n = libusb_get_string_descriptor_ascii(h, d.iSerialNumber, buf, sizeof buf);
  return n > 0 ? std::string(reinterpret_cast<char*>(buf), static_cast<std::size_t>(n)) : std::string();
}

// libusb's hotplug callback: a device the vendor/product filter admits has arrived (the whole selector is checked
// when opening it). Stays registered.
int LIBUSB_CALL on_arrival(libusb_context*, libusb_device*, libusb_hotplug_event, void* arrived) {
  static_cast<std::atomic<bool>*>(arrived)->store(true);
  return 0;
}

// Registers on_arrival for the devices `s` could match; libusb's code.
int register_arrivals(libusb_context* ctx, const DeviceSelector& s, std::atomic<bool>* arrived,
                      libusb_hotplug_callback_handle* handle) {
  const int vid = s.vendor_id ? *s.vendor_id : LIBUSB_HOTPLUG_MATCH_ANY;
  const int pid = s.product_id ? *s.product_id : LIBUSB_HOTPLUG_MATCH_ANY;
  return libusb_hotplug_register_callback(ctx, LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED, LIBUSB_HOTPLUG_NO_FLAGS, vid, pid,
                                          LIBUSB_HOTPLUG_MATCH_ANY, &on_arrival, arrived, handle);
}

// Chooses how to notice the device's return and registers the callback when it is hotplug; *registered says
// whether a callback is now registered (to remove before libusb_exit).
ReconnectPlan setup_reconnect(libusb_context* ctx, const UsbOptions& o, std::atomic<bool>* arrived,
                              libusb_hotplug_callback_handle* handle, bool* registered) {
  const bool has = usb_has_hotplug();
  const int code = o.hotplug && has ? register_arrivals(ctx, o.device, arrived, handle) : LIBUSB_ERROR_NOT_SUPPORTED;
  *registered = o.hotplug && has && code == 0;
  return plan_reconnect(o.hotplug, has, code, o.reconnect_poll);
}

}  // namespace

ReconnectPlan plan_reconnect(bool wanted, bool platform_has_hotplug, int register_code,
                             std::chrono::milliseconds poll) {
  ReconnectPlan p;
  if (wanted && platform_has_hotplug && register_code == 0) {
    p.mode = ReconnectMode::hotplug;
    p.message = "libusb hotplug events";
    return p;
  }
  p.mode = ReconnectMode::polling;
  p.message = "polling every " + std::to_string(poll.count()) + " ms (";
  if (!wanted)
    p.message += "hotplug turned off";
  else if (!platform_has_hotplug)
    p.message += "libusb has no hotplug support on this platform";
  else
    p.message += std::string("registering the hotplug callback failed: ") + libusb_error_name(register_code);
  p.message += ")";
  return p;
}

bool usb_has_hotplug() { return libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG) != 0; }

ReconnectPlan usb_reconnect_plan(const UsbOptions& options) {
  libusb_context* ctx = nullptr;
  if (int r = libusb_init(&ctx); r != 0)
    throw Error(std::string("USB unavailable: libusb_init failed (") + libusb_error_name(r) + ")");
  std::atomic<bool> arrived{false};
  libusb_hotplug_callback_handle handle{};
  bool registered = false;
  const ReconnectPlan plan = setup_reconnect(ctx, options, &arrived, &handle, &registered);
  if (registered) libusb_hotplug_deregister_callback(ctx, handle);
  libusb_exit(ctx);
  return plan;
}

DeviceSelector DeviceSelector::parse(const std::string& text) {
  DeviceSelector s;
  if (text.empty()) throw Error("--device: empty device (give a serial number, VID:PID or BUS-PORT)");
  if (auto colon = text.find(':'); colon != std::string::npos) {
    auto vid = parse_number(text.substr(0, colon), 16), pid = parse_number(text.substr(colon + 1), 16);
    if (!vid || !pid || *vid < 0 || *vid > 0xffff || *pid < 0 || *pid > 0xffff)
      throw Error("--device " + text + ": VID:PID must be two 4-digit hex numbers, e.g. 16c0:05dc");
    s.vendor_id = static_cast<std::uint16_t>(*vid);
    s.product_id = static_cast<std::uint16_t>(*pid);
    return s;
  }
  if (auto dash = text.find('-'); dash != std::string::npos && parse_number(text.substr(0, dash), 10)) {
    s.bus = static_cast<int>(*parse_number(text.substr(0, dash), 10));
    std::string rest = text.substr(dash + 1);
    for (std::size_t at = 0; at <= rest.size();) {
      auto dot = rest.find('.', at);
      auto port = parse_number(rest.substr(at, dot == std::string::npos ? std::string::npos : dot - at), 10);
      if (!port || *port < 1 || *port > 255)
        throw Error("--device " + text + ": BUS-PORT must be numbers like 3-1.2 (bus 3, port 1, hub port 2)");
      s.ports.push_back(static_cast<int>(*port));
      if (dot == std::string::npos) break;
      at = dot + 1;
    }
    return s;
  }
  s.serial = text;
  return s;
}

std::string DeviceSelector::describe() const {
  if (vendor_id) return hex4(*vendor_id) + ":" + hex4(*product_id ? *product_id : 0);
  if (bus >= 0) {
    std::string t = std::to_string(bus) + "-";
    for (std::size_t i = 0; i < ports.size(); ++i) t += (i ? "." : "") + std::to_string(ports[i]);
    return t;
  }
  return "serial " + serial;
}

std::string describe_usb_error(int code, const std::string& what, const std::string& device) {
  std::string m = "tactile sensor " + device + ": " + what + " failed (" + libusb_error_name(code) + ")";
  if (code == LIBUSB_ERROR_ACCESS)
    m += ": no permission to open it; add a udev rule for its vendor/product id (docs/usb-sensor.md) or run as root";
  else if (code == LIBUSB_ERROR_BUSY)
    m += ": another program or kernel driver holds the interface";
  else if (code == LIBUSB_ERROR_NO_DEVICE)
    m += ": the device was unplugged";
  else if (code == LIBUSB_ERROR_NOT_FOUND)
    m += ": no such interface or endpoint on this device (check --interface and --endpoint)";
  return m;
}

std::vector<UsbDeviceInfo> list_usb_devices() {
  libusb_context* ctx = nullptr;
  if (int r = libusb_init(&ctx); r != 0)
    throw Error(std::string("USB unavailable: libusb_init failed (") + libusb_error_name(r) + ")");
  libusb_device** list = nullptr;
  ssize_t n = libusb_get_device_list(ctx, &list);
  std::vector<UsbDeviceInfo> out;
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
    UsbDeviceInfo info{
        d.idVendor,         d.idProduct, libusb_get_bus_number(list[i]), libusb_get_device_address(list[i]),
        port_path(list[i]), {}};
    libusb_device_handle* h = nullptr;
    if (libusb_open(list[i], &h) == 0) {
      info.serial = read_serial(h, d);
      libusb_close(h);
    }
    out.push_back(std::move(info));
  }
  if (list) libusb_free_device_list(list, 1);
  libusb_exit(ctx);
  if (n < 0)
    throw Error(std::string("USB unavailable: cannot list devices (") + libusb_error_name(static_cast<int>(n)) + ")");
  return out;
}

struct UsbTransport::Impl {
  UsbOptions options;
  libusb_context* ctx = nullptr;
  libusb_device_handle* handle = nullptr;
  bool claimed = false;
  std::vector<libusb_transfer*> transfers;
  std::vector<std::vector<unsigned char>> buffers;
  int active = 0;     // transfers submitted and not yet returned
  bool lost = false;  // a transfer reported the device gone
  std::string lost_reason;
  std::deque<Chunk> pending;
  std::atomic<bool> interrupted{false};
  bool ended = false;
  // Reconnecting: the plan, the hotplug callback's flag, and until when to try opening (a device that has just
  // arrived may not be openable at once: udev applies its permissions after the event).
  ReconnectPlan plan;
  std::atomic<bool> arrived{false};
  libusb_hotplug_callback_handle hotplug_handle{};
  bool hotplug_registered = false;
  std::int64_t try_open_until_ns = 0;

  ~Impl() {
    release();
    if (hotplug_registered) libusb_hotplug_deregister_callback(ctx, hotplug_handle);
    if (ctx) libusb_exit(ctx);
  }
  bool device_may_be_back(std::chrono::milliseconds timeout);
  int open_matching(std::string* why);
  void check_endpoint();
  void start();
  void release();
  static void LIBUSB_CALL on_transfer(libusb_transfer* t);
};

int UsbTransport::Impl::open_matching(std::string* why) {
  libusb_device** list = nullptr;
  ssize_t n = libusb_get_device_list(ctx, &list);
  if (n < 0) return static_cast<int>(n);
  int result = LIBUSB_ERROR_NOT_FOUND;
  const DeviceSelector& s = options.device;
  for (ssize_t i = 0; i < n && !handle; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
    if (s.vendor_id && (d.idVendor != *s.vendor_id || d.idProduct != *s.product_id)) continue;
    if (s.bus >= 0 && (libusb_get_bus_number(list[i]) != s.bus || port_path(list[i]) != s.ports)) continue;
    if (s.serial.empty() || d.iSerialNumber) {
      libusb_device_handle* h = nullptr;
      if (int r = libusb_open(list[i], &h); r != 0) {
        result = r;  // remember why a candidate could not be opened (permission)
        if (why)
          *why = "bus " + std::to_string(libusb_get_bus_number(list[i])) + " device " +
                 std::to_string(libusb_get_device_address(list[i]));
        continue;
      }
      if (!s.serial.empty() && read_serial(h, d) != s.serial) {
        libusb_close(h);
        continue;
      }
      handle = h;
      result = 0;
    }
  }
  libusb_free_device_list(list, 1);
  return result;
}

void UsbTransport::Impl::check_endpoint() {
  const std::string device = options.device.describe();
  libusb_config_descriptor* config = nullptr;
  if (int r = libusb_get_active_config_descriptor(libusb_get_device(handle), &config); r != 0)
    throw Error(describe_usb_error(r, "reading its configuration", device));
  bool found = false, bulk_in = false;
  for (int i = 0; i < config->bNumInterfaces; ++i) {
    if (config->interface[i].num_altsetting < 1) continue;
    const auto& alt = config->interface[i].altsetting[0];
    if (alt.bInterfaceNumber != options.interface_number) continue;
    for (int e = 0; e < alt.bNumEndpoints; ++e)
      if (alt.endpoint[e].bEndpointAddress == options.endpoint) {
        found = true;
        bulk_in = (alt.endpoint[e].bmAttributes & 3) == LIBUSB_TRANSFER_TYPE_BULK;
      }
  }
  libusb_free_config_descriptor(config);
  char ep[8];
  std::snprintf(ep, sizeof ep, "0x%02x", options.endpoint);
  if (!found)
    throw Error("tactile sensor " + device + ": interface " + std::to_string(options.interface_number) +
                " has no endpoint " + ep + " (wrong --endpoint or --interface)");
  if (!bulk_in) throw Error("tactile sensor " + device + ": endpoint " + ep + " is not a bulk endpoint");
}

void UsbTransport::Impl::start() {
  libusb_set_auto_detach_kernel_driver(handle, 1);
  if (int r = libusb_claim_interface(handle, options.interface_number); r != 0)
    throw Error(describe_usb_error(r, "claiming interface " + std::to_string(options.interface_number),
                                   options.device.describe()));
  claimed = true;
  lost = false;
  buffers.assign(static_cast<std::size_t>(options.transfers_in_flight),
                 std::vector<unsigned char>(options.transfer_bytes));
  for (auto& buffer : buffers) {
    libusb_transfer* t = libusb_alloc_transfer(0);
    if (!t) throw Error("tactile sensor: out of memory for USB transfers");
    transfers.push_back(t);
    libusb_fill_bulk_transfer(t, handle, options.endpoint, buffer.data(), static_cast<int>(buffer.size()),
                              &Impl::on_transfer, this, 0);
    if (int r = libusb_submit_transfer(t); r != 0)
      throw Error(describe_usb_error(r, "submitting a bulk transfer", options.device.describe()));
    ++active;
  }
}

void LIBUSB_CALL UsbTransport::Impl::on_transfer(libusb_transfer* t) {
  auto* self = static_cast<Impl*>(t->user_data);
  if (t->status == LIBUSB_TRANSFER_COMPLETED || t->status == LIBUSB_TRANSFER_TIMED_OUT) {
    if (t->actual_length > 0)
      self->pending.push_back(Chunk{
          LinkStatus::data, monotonic_ns(), std::vector<std::uint8_t>(t->buffer, t->buffer + t->actual_length), {}});
    if (!self->lost && libusb_submit_transfer(t) == 0) return;
  } else if (t->status != LIBUSB_TRANSFER_CANCELLED) {
    self->lost = true;
    self->lost_reason = t->status == LIBUSB_TRANSFER_NO_DEVICE ? "device unplugged" : "transfer error";
  }
  --self->active;
}

void UsbTransport::Impl::release() {
  for (auto* t : transfers) libusb_cancel_transfer(t);
  // Cancelled transfers return through the event loop; wait for them before freeing (bounded: 2 s).
  for (int i = 0; i < 200 && active > 0; ++i) {
    timeval tv{0, 10000};
    libusb_handle_events_timeout_completed(ctx, &tv, nullptr);
  }
  for (auto* t : transfers) libusb_free_transfer(t);
  transfers.clear();
  active = 0;
  if (claimed) libusb_release_interface(handle, options.interface_number);
  claimed = false;
  if (handle) libusb_close(handle);
  handle = nullptr;
}

UsbTransport::UsbTransport(UsbOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
  const auto& o = impl_->options;
  char ep[8];
  std::snprintf(ep, sizeof ep, "0x%02x", o.endpoint);
  if (!(o.endpoint & 0x80))
    throw Error(std::string("--endpoint ") + ep +
                " is an OUT endpoint; frames come from a bulk IN endpoint (0x81..0x8f)");
  if (o.transfer_bytes < 64 || o.transfers_in_flight < 1)
    throw Error("USB transfers need >= 64 bytes and >= 1 in flight");
  if (int r = libusb_init(&impl_->ctx); r != 0)
    throw Error(std::string("USB unavailable: libusb_init failed (") + libusb_error_name(r) + ")");
  std::string which;
  int r = impl_->open_matching(&which);
  if (r == LIBUSB_ERROR_NOT_FOUND)
    throw Error("no tactile sensor " + o.device.describe() + " found (is it plugged in? `lsusb` lists devices)");
  if (r != 0) throw Error(describe_usb_error(r, "opening " + which, o.device.describe()));
  impl_->check_endpoint();
  impl_->start();
  impl_->plan = setup_reconnect(impl_->ctx, o, &impl_->arrived, &impl_->hotplug_handle, &impl_->hotplug_registered);
}

UsbTransport::~UsbTransport() = default;

const ReconnectPlan& UsbTransport::reconnect_plan() const { return impl_->plan; }

// Waits up to `timeout` for a sign that the device is back: with hotplug, an arrival event (then opening is tried
// for 5 s); polling, every reconnect_poll.
bool UsbTransport::Impl::device_may_be_back(std::chrono::milliseconds timeout) {
  const auto wait = std::min(timeout, options.reconnect_poll);
  if (plan.mode == ReconnectMode::polling) {
    std::this_thread::sleep_for(wait);
    return true;
  }
  const auto us = std::chrono::duration_cast<std::chrono::microseconds>(wait).count();
  timeval tv{static_cast<time_t>(us / 1000000), static_cast<suseconds_t>(us % 1000000)};
  libusb_handle_events_timeout_completed(ctx, &tv, nullptr);  // delivers hotplug callbacks
  if (arrived.exchange(false)) try_open_until_ns = monotonic_ns() + 5'000'000'000;
  return monotonic_ns() < try_open_until_ns;
}

void UsbTransport::interrupt() {
  impl_->interrupted = true;
  if (impl_->ctx) libusb_interrupt_event_handler(impl_->ctx);
}

std::string UsbTransport::describe() const { return "USB " + impl_->options.device.describe(); }

Chunk UsbTransport::read(std::chrono::milliseconds timeout) {
  Impl& m = *impl_;
  if (m.ended || m.interrupted) {
    m.ended = true;
    return Chunk{LinkStatus::ended, monotonic_ns(), {}, "stopped"};
  }
  if (!m.pending.empty()) {
    Chunk c = std::move(m.pending.front());
    m.pending.pop_front();
    return c;
  }
  if (m.handle) {
    const auto us = std::chrono::duration_cast<std::chrono::microseconds>(timeout).count();
    timeval tv{static_cast<time_t>(us / 1000000), static_cast<suseconds_t>(us % 1000000)};
    libusb_handle_events_timeout_completed(m.ctx, &tv, nullptr);
    if (!m.pending.empty()) return read(timeout);
    if (m.lost || m.active == 0) {
      std::string reason = m.lost_reason.empty() ? "all transfers stopped" : m.lost_reason;
      m.release();
      // One try at once: the device may be back before the first event is handled.
      m.try_open_until_ns = monotonic_ns() + std::chrono::nanoseconds(m.options.reconnect_poll).count();
      return Chunk{LinkStatus::disconnected,
                   monotonic_ns(),
                   {},
                   describe() + ": " + reason + "; reconnecting by " + m.plan.message};
    }
    return Chunk{LinkStatus::idle, monotonic_ns(), {}, {}};
  }
  // Disconnected: wait for the same device (by the same selector) to return.
  if (!m.device_may_be_back(timeout) || m.open_matching(nullptr) != 0)
    return Chunk{LinkStatus::idle, monotonic_ns(), {}, {}};
  try {
    m.check_endpoint();
    m.start();
  } catch (const Error& e) {
    m.ended = true;
    return Chunk{LinkStatus::failed, monotonic_ns(), {}, e.what()};
  }
  return Chunk{LinkStatus::reconnected, monotonic_ns(), {}, describe() + ": reconnected (" + m.plan.message + ")"};
}

}  // namespace sva::drivers
