#pragma once
// How throng-view prints its URL: the address a browser on this machine can open.
#include <string>

namespace throng::view {

inline std::string display_host(const std::string& bind) {
  if (bind == "0.0.0.0" || bind == "127.0.0.1") return "127.0.0.1";
  if (bind == "::" || bind == "::1") return "[::1]";
  return bind.find(':') != std::string::npos ? "[" + bind + "]" : bind;
}

}  // namespace throng::view
