// printer::Link over a serial port with libserialport: USB boards (/dev/ttyUSB0, /dev/ttyACM0)
// and pseudo-terminals (`mahost sim --pty`).
//
// Opens by path at a baud rate, 8N1, no flow control, with the port locked against other
// programs (flock and TIOCEXCL, as pyserial's exclusive mode). Its input is emptied right
// after opening, before anything else: a board that resets as the port opens (DTR) must not
// have its `start` thrown away by a flush that comes late (the job does not rely on seeing it:
// printer/job.h asks the printer where Z is). Then it drops and raises DTR so a board that
// resets on it (Arduino-style Marlin boards) starts fresh. For tests, MAHOST_DELAY_AFTER_OPEN_MS
// holds the host between opening and emptying the input. Every failure is a LinkError naming the port and what to do: missing,
// busy, no permission, vanished mid-print. Time is the steady clock.
// libserialport 0.1 finds ports through sysfs, where pseudo-terminals are not; a terminal it
// does not know is driven through termios directly (raw, 8N1), the same way.
#pragma once

#include <chrono>
#include <string>
#include <string_view>
#include <vector>

#include "printer/link.h"

struct sp_port;

namespace printer {

class SerialLink : public Link {
 public:
  SerialLink(std::string path, int baud);
  ~SerialLink() override;
  SerialLink(const SerialLink&) = delete;
  SerialLink& operator=(const SerialLink&) = delete;

  void write(std::string_view bytes) override;
  std::string read(std::chrono::milliseconds timeout) override;
  std::chrono::nanoseconds now() const override;
  std::string name() const override { return path_; }

 private:
  [[noreturn]] void vanished(const char* doing) const;
  void open_terminal(int baud);
  std::string path_;
  sp_port* port_ = nullptr;
  int fd_ = -1;  // the termios path, when libserialport does not know the device
};

// The serial speeds a port can be opened at (bit/s, ascending), and the same as text for
// messages: "9600, 19200, ..., 115200, 250000, ...".
const std::vector<int>& standard_baud_rates();
std::string standard_baud_rates_text();

// Checks, without opening it, that `path` is a device this user may open: throws the
// LinkError opening it would (no such port, permission denied), naming the port. Cheap, so a
// job checks its port before slicing for minutes; opening would reset many boards (DTR).
void check_serial_port(const std::string& path);

struct SerialPortInfo {
  std::string path;         // /dev/ttyUSB0
  std::string description;  // libserialport's description ("USB2.0-Serial")
  std::string transport;    // "usb", "native", "bluetooth"
  int usb_vendor = -1, usb_product = -1;
  std::string manufacturer, product, serial_number;
};

// The serial ports libserialport finds (pseudo-terminals are not listed).
std::vector<SerialPortInfo> list_serial_ports();

}  // namespace printer
