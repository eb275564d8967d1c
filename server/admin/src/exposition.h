// Text exposition format 0.0.4 details shared by registration (validation, pre-rendered label
// strings) and render() (numbers): https://prometheus.io/docs/instrumenting/exposition_formats/
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace throng::admin::exposition {

// [a-zA-Z_:][a-zA-Z0-9_:]*
bool valid_metric_name(std::string_view name) noexcept;
// [a-zA-Z_][a-zA-Z0-9_]*
bool valid_label_name(std::string_view name) noexcept;

// Label values escape backslash, double quote and newline; HELP text escapes backslash and newline.
void append_escaped_label_value(std::string& out, std::string_view value);
void append_escaped_help(std::string& out, std::string_view help);

// Shortest text that parses back to the same double (plain notation for magnitudes in [1e-4, 1e21));
// +Inf / -Inf / NaN as Prometheus spells them.
void append_double(std::string& out, double v);
void append_uint(std::string& out, std::uint64_t v);

}  // namespace throng::admin::exposition
