// `mahost ports`: the serial ports libserialport finds, with their USB descriptions, so a user
// knows what to give --port.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "host/commands.h"
#include "printer/serial_link.h"

namespace host {

void add_ports_command(CLI::App& app) {
  auto* ports = app.add_subcommand("ports", "List the serial ports a printer may be on");
  ports->footer("Each port with its USB description, vendor and product ids; give one to "
                "mahost print --port.");
  ports->callback([] {
    const auto found = printer::list_serial_ports();
    if (found.empty()) {
      fmt::print("no serial ports found (is the printer plugged in and powered? `mahost sim` "
                 "makes a simulated one)\n");
      return;
    }
    for (const printer::SerialPortInfo& p : found) {
      std::string line = fmt::format("{:<16} {}", p.path, p.description);
      if (p.transport == "usb") {
        if (p.usb_vendor >= 0) line += fmt::format("  usb {:04x}:{:04x}", p.usb_vendor, p.usb_product);
        if (!p.manufacturer.empty()) line += "  " + p.manufacturer;
        if (!p.product.empty()) line += " " + p.product;
        if (!p.serial_number.empty()) line += "  serial " + p.serial_number;
      } else {
        line += "  (" + p.transport + ")";
      }
      fmt::print("{}\n", line);
    }
  });
}

}  // namespace host
