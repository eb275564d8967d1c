#include "throng/protocol/contacts.h"

#include <cmath>

#include "cdr_size.h"

namespace throng::protocol {

namespace {
std::uint16_t quantize(double v, double scale) {
  if (!(v > 0.0)) return 0;  // also NaN
  const double q = std::round(v * scale);
  return q >= 65535.0 ? std::uint16_t{65535} : static_cast<std::uint16_t>(q);
}
}  // namespace

std::uint16_t quantize_share(double share) { return quantize(share > 1.0 ? 1.0 : share, kShareScale); }
double dequantize_share(std::uint16_t q) { return q / kShareScale; }
std::uint16_t quantize_contact_m(double metres) { return quantize(metres, 1.0 / kContactUnitM); }
double dequantize_contact_m(std::uint16_t q) { return q * kContactUnitM; }

void push_contact(ContactPairs& m, std::uint32_t a, std::uint32_t b, double share_a, double depth_m, double push_m) {
  m.a.push_back(a);
  m.b.push_back(b);
  m.share_a.push_back(quantize_share(share_a));
  m.depth.push_back(quantize_contact_m(depth_m));
  m.push.push_back(quantize_contact_m(push_m));
}

std::optional<std::string> check_contact_pairs(const ContactPairs& m) {
  const std::size_t n = m.a.size();
  if (m.b.size() != n || m.share_a.size() != n || m.depth.size() != n || m.push.size() != n)
    return "contact pairs: arrays of different lengths";
  if (n > m.pairs_near) return "contact pairs: more pairs than pairs_near";
  for (std::size_t i = 0; i < n; ++i)
    if (m.a[i] == 0 || m.b[i] == 0) return "contact pairs: object id 0 in pair " + std::to_string(i);
  if (!std::isfinite(m.camera_x) || !std::isfinite(m.camera_y) || !std::isfinite(m.radius_m))
    return "contact pairs: non-finite camera or radius";
  return std::nullopt;
}

std::size_t contact_pairs_wire_bytes(const ContactPairs& m) {
  detail::CdrSize c;
  c.prim(4);  // client_id
  c.prim(8);  // tick
  c.prim(4);  // pairs_near
  c.prim(4);  // camera_x
  c.prim(4);  // camera_y
  c.prim(4);  // radius_m
  c.seq(m.a.size(), 4);
  c.seq(m.b.size(), 4);
  c.seq(m.share_a.size(), 2);
  c.seq(m.depth.size(), 2);
  c.seq(m.push.size(), 2);
  return c.n + 4;  // + the 4-byte encapsulation header
}

}  // namespace throng::protocol
