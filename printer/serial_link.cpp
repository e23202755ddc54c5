#include "printer/serial_link.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <thread>

#include <fmt/core.h>
#include <libserialport.h>

#include "printer/error.h"

namespace printer {

namespace {

// For tests: MAHOST_DELAY_AFTER_OPEN_MS=<ms> holds the host that long between opening the port
// and emptying its input, as a host descheduled there would be (the fault that made a resume
// lose the board's `start`). Unset or not a number: no delay.
void delay_after_open() {
  const char* text = std::getenv("MAHOST_DELAY_AFTER_OPEN_MS");
  if (text == nullptr) return;
  char* end = nullptr;
  const long ms = std::strtol(text, &end, 10);
  if (end != text && *end == '\0' && ms > 0 && ms < 60000) {
    std::this_thread::sleep_for(std::chrono::milliseconds(ms));
  }
}

std::string open_failure(const std::string& path, int error) {
  switch (error) {
    case EACCES:
    case EPERM:
      return fmt::format(
          "{}: permission denied: add yourself to the 'dialout' group (sudo usermod -aG dialout "
          "$USER, then log in again)",
          path);
    case EBUSY:
      return fmt::format(
          "{}: the port is busy: another program (OctoPrint, a slicer, ModemManager, another "
          "mahost) has it open; close it and retry",
          path);
    case ENOENT:
    case ENODEV:
    case ENXIO:
      return fmt::format("{}: no such serial port: is the printer plugged in? `mahost ports` lists the ports found", path);
    default:
      return fmt::format("{}: cannot open the serial port: {}", path, std::strerror(error));
  }
}

}  // namespace

void check_serial_port(const std::string& path) {
  struct stat info{};
  if (::stat(path.c_str(), &info) != 0) throw LinkError(open_failure(path, errno));
  if (!S_ISCHR(info.st_mode)) {
    throw LinkError(fmt::format(
        "{}: is not a serial port or terminal: `mahost ports` lists the ports found", path));
  }
  if (::access(path.c_str(), R_OK | W_OK) != 0) throw LinkError(open_failure(path, errno));
}

const std::vector<int>& standard_baud_rates() {
  static const std::vector<int> rates{9600,   19200,  38400,  57600,  115200,  230400,
                                      250000, 460800, 500000, 921600, 1000000};
  return rates;
}

std::string standard_baud_rates_text() {
  std::string text;
  for (const int rate : standard_baud_rates()) text += (text.empty() ? "" : ", ") + std::to_string(rate);
  return text;
}

SerialLink::SerialLink(std::string path, int baud) : path_(std::move(path)) {
  if (baud <= 0) throw ConfigError(fmt::format("--baud {}: give a positive rate such as 115200 or 250000", baud));
  check_serial_port(path_);
  if (sp_get_port_by_name(path_.c_str(), &port_) != SP_OK) {
    port_ = nullptr;
    open_terminal(baud);
    return;
  }
  if (sp_open(port_, SP_MODE_READ_WRITE) != SP_OK) {
    const int error = sp_last_error_code();
    sp_free_port(port_);
    port_ = nullptr;
    throw LinkError(open_failure(path_, error));
  }
  // What was there before this session goes, at once: whatever the board says from now on (a
  // `start` after the DTR reset below) is the engine's to read.
  delay_after_open();
  sp_flush(port_, SP_BUF_INPUT);
  int fd = -1;
  if (sp_get_port_handle(port_, &fd) == SP_OK && fd >= 0) {
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
      sp_close(port_);
      sp_free_port(port_);
      port_ = nullptr;
      throw LinkError(open_failure(path_, EBUSY));
    }
    ioctl(fd, TIOCEXCL);
  }
  sp_port_config* config = nullptr;
  bool configured = sp_new_config(&config) == SP_OK;
  configured = configured && sp_get_config(port_, config) == SP_OK;
  configured = configured && sp_set_config_baudrate(config, baud) == SP_OK &&
               sp_set_config_bits(config, 8) == SP_OK &&
               sp_set_config_parity(config, SP_PARITY_NONE) == SP_OK &&
               sp_set_config_stopbits(config, 1) == SP_OK &&
               sp_set_config_flowcontrol(config, SP_FLOWCONTROL_NONE) == SP_OK &&
               sp_set_config(port_, config) == SP_OK;
  if (config != nullptr) sp_free_config(config);
  if (!configured) {
    const std::string why = sp_last_error_message();
    sp_close(port_);
    sp_free_port(port_);
    port_ = nullptr;
    throw LinkError(fmt::format("{}: cannot set {} baud, 8N1: {}", path_, baud, why));
  }
  // Drop and raise DTR: a board that resets on it starts fresh (a pseudo-terminal has no DTR;
  // the error is ignored there).
  if (sp_set_dtr(port_, SP_DTR_OFF) == SP_OK) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    sp_set_dtr(port_, SP_DTR_ON);
  }
}

void SerialLink::open_terminal(int baud) {
  fd_ = ::open(path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) throw LinkError(open_failure(path_, errno));
  delay_after_open();
  tcflush(fd_, TCIFLUSH);  // at once, as above
  if (!::isatty(fd_)) {
    ::close(fd_);
    fd_ = -1;
    throw LinkError(fmt::format("{}: is not a serial port or terminal", path_));
  }
  if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw LinkError(open_failure(path_, EBUSY));
  }
  ioctl(fd_, TIOCEXCL);
  termios t{};
  if (tcgetattr(fd_, &t) == 0) {
    cfmakeraw(&t);
    t.c_cflag |= CLOCAL | CREAD;
    t.c_cflag &= ~static_cast<tcflag_t>(CRTSCTS | CSTOPB | PARENB);
    speed_t speed = B0;
    switch (baud) {
      case 9600: speed = B9600; break;
      case 19200: speed = B19200; break;
      case 38400: speed = B38400; break;
      case 57600: speed = B57600; break;
      case 115200: speed = B115200; break;
      case 230400: speed = B230400; break;
      default: break;  // a pseudo-terminal has no speed; a real port would need termios2
    }
    if (speed != B0) cfsetspeed(&t, speed);
    tcsetattr(fd_, TCSANOW, &t);
  }
}

SerialLink::~SerialLink() {
  if (fd_ >= 0) ::close(fd_);
  if (port_ != nullptr) {
    sp_drain(port_);
    sp_close(port_);
    sp_free_port(port_);
  }
}

void SerialLink::vanished(const char* doing) const {
  throw LinkError(fmt::format(
      "{}: the port vanished while {} (unplugged, or the printer lost power); reconnect it",
      path_, doing));
}

void SerialLink::write(std::string_view bytes) {
  if (fd_ >= 0) {
    std::size_t done = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (done < bytes.size()) {
      const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
      if (n > 0) {
        done += static_cast<std::size_t>(n);
        continue;
      }
      if (n < 0 && errno != EAGAIN && errno != EINTR) vanished("writing");
      if (std::chrono::steady_clock::now() > deadline) {
        throw LinkError(fmt::format("{}: the port took no data for 5 s", path_));
      }
      pollfd p{fd_, POLLOUT, 0};
      ::poll(&p, 1, 100);
      if (p.revents & (POLLHUP | POLLERR)) vanished("writing");
    }
    return;
  }
  const sp_return written = sp_blocking_write(port_, bytes.data(), bytes.size(), 5000);
  if (written < 0) vanished("writing");
  if (static_cast<std::size_t>(written) < bytes.size()) {
    throw LinkError(fmt::format("{}: the port took no data for 5 s: is hardware flow control on?", path_));
  }
}

std::string SerialLink::read(std::chrono::milliseconds timeout) {
  char buffer[4096];
  if (fd_ >= 0) {
    pollfd p{fd_, POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::max<long long>(0, timeout.count())));
    if (ready < 0 && errno != EINTR) vanished("reading");
    if (ready <= 0) return {};
    const ssize_t n = ::read(fd_, buffer, sizeof buffer);
    if (n > 0) return std::string(buffer, static_cast<std::size_t>(n));
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) return {};
    vanished("reading");  // EOF or EIO: the other end closed
  }
  sp_return got;
  if (timeout.count() <= 0) {
    got = sp_nonblocking_read(port_, buffer, sizeof buffer);
  } else {
    got = sp_blocking_read_next(port_, buffer, sizeof buffer, static_cast<unsigned>(timeout.count()));
  }
  if (got < 0) vanished("reading");
  // A port whose device is gone reads as ready with no bytes; tell that from a timeout.
  if (got == 0 && !std::filesystem::exists(path_)) vanished("reading");
  std::string bytes(buffer, static_cast<std::size_t>(got));
  if (got > 0) {
    // Take whatever else is already there in the same call.
    const sp_return more = sp_nonblocking_read(port_, buffer, sizeof buffer);
    if (more > 0) bytes.append(buffer, static_cast<std::size_t>(more));
  }
  return bytes;
}

std::chrono::nanoseconds SerialLink::now() const {
  return std::chrono::steady_clock::now().time_since_epoch();
}

std::vector<SerialPortInfo> list_serial_ports() {
  std::vector<SerialPortInfo> found;
  sp_port** ports = nullptr;
  if (sp_list_ports(&ports) != SP_OK) return found;
  for (sp_port** p = ports; *p != nullptr; ++p) {
    SerialPortInfo info;
    auto text = [](const char* s) { return s != nullptr ? std::string(s) : std::string(); };
    info.path = text(sp_get_port_name(*p));
    info.description = text(sp_get_port_description(*p));
    switch (sp_get_port_transport(*p)) {
      case SP_TRANSPORT_USB: {
        info.transport = "usb";
        int vid = -1, pid = -1;
        if (sp_get_port_usb_vid_pid(*p, &vid, &pid) == SP_OK) {
          info.usb_vendor = vid;
          info.usb_product = pid;
        }
        info.manufacturer = text(sp_get_port_usb_manufacturer(*p));
        info.product = text(sp_get_port_usb_product(*p));
        info.serial_number = text(sp_get_port_usb_serial(*p));
        break;
      }
      case SP_TRANSPORT_BLUETOOTH: info.transport = "bluetooth"; break;
      default: info.transport = "native"; break;
    }
    found.push_back(std::move(info));
  }
  sp_free_port_list(ports);
  return found;
}

}  // namespace printer
