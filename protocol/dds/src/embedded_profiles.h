#pragma once
// The text of protocol/dds/qos/throng_profiles.xml, embedded at build time so the transports load
// their QoS from memory, independent of the working directory and of where binaries are installed.
#include <string_view>

namespace throng::protocol::dds_detail {

extern const char* const kProfilesSourcePath;  // where the text came from, for error messages
extern const std::string_view kProfilesXml;

}  // namespace throng::protocol::dds_detail
