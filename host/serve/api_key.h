// The API key of `mahost serve`: the one secret every API call and the web page must show
// (sent as the X-Api-Key header, as OctoPrint's clients send it).
//
// Taken from the environment variable MAHOST_API_KEY when it is set (services, tests), else
// read from <config>/mahost/api-key, where <config> is $XDG_CONFIG_HOME or ~/.config. At the
// first start that file is made: 32 hex digits (128 bits) from the kernel's random source,
// written with mode 0600 in a folder of mode 0700. A key file that others may read is
// refused, as ssh refuses such a private key.
#pragma once

#include <string>
#include <string_view>

namespace host::serve {

struct ApiKey {
  std::string value;
  std::string source;    // "MAHOST_API_KEY" or the file's path
  bool created = false;  // made just now: the user has not seen it yet
};

// Throws printer::ConfigError naming the file or variable and what to do: a key file that
// cannot be made or read, one readable by group or others, a key shorter than 16 characters
// or with characters outside [A-Za-z0-9_-].
ApiKey load_api_key();

// Where the key file lives for the current environment.
std::string api_key_path();

// A fresh key: 32 hex digits.
std::string make_api_key();

// Compares in time independent of where the strings differ, so a guess learns nothing from
// how long the refusal took.
bool same_key(std::string_view given, std::string_view expected);

}  // namespace host::serve
