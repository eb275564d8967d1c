#include "conversions.h"

#include <type_traits>
#include <utility>

#include "throng/protocol/message_fields.h"

namespace throng::protocol::dds_detail {

// Every conversion expands the message's field list (message_fields.h): s.f(to_wire(m.f)) to the
// wire, m.f = from_wire<decltype(m.f)>(s.f()) from it. Enum values travel as octets; the nested
// scenery and roster have conversions of their own.
namespace {

v1::SceneryShape to_idl(const SceneryShape& m);
v1::RosterArrays to_idl(const Roster& m);
SceneryShape from_idl(v1::SceneryShape&& s);
Roster from_idl(v1::RosterArrays&& s);

template <class T>
decltype(auto) to_wire(const T& v) {
  if constexpr (std::is_enum_v<T>) {
    return static_cast<std::uint8_t>(v);
  } else if constexpr (std::is_same_v<T, Roster>) {
    return to_idl(v);
  } else if constexpr (std::is_same_v<T, std::vector<SceneryShape>>) {
    std::vector<v1::SceneryShape> out;
    out.reserve(v.size());
    for (const SceneryShape& shape : v) out.push_back(to_idl(shape));
    return out;
  } else {
    return (v);  // a reference: strings and arrays are copied once, by the setter
  }
}

template <class T, class W>
T from_wire(W& w) {
  if constexpr (std::is_enum_v<T>) {
    return static_cast<T>(w);
  } else if constexpr (std::is_same_v<T, Roster>) {
    return from_idl(std::move(w));
  } else if constexpr (std::is_same_v<T, std::vector<SceneryShape>>) {
    T out;
    out.reserve(w.size());
    for (v1::SceneryShape& shape : w) out.push_back(from_idl(std::move(shape)));
    return out;
  } else {
    return std::move(w);  // the sample is the caller's rvalue: strings and arrays move out
  }
}

}  // namespace

#define THRONG_TO_WIRE(f) s.f(to_wire(m.f));
#define THRONG_FROM_WIRE(f) m.f = from_wire<decltype(m.f)>(s.f());
#define THRONG_CONVERSIONS(Message, Idl, FIELDS) \
  Idl to_idl(const Message& m) {                 \
    Idl s;                                       \
    FIELDS(THRONG_TO_WIRE)                       \
    return s;                                    \
  }                                              \
  Message from_idl(Idl&& s) {                    \
    Message m;                                   \
    FIELDS(THRONG_FROM_WIRE)                     \
    return m;                                    \
  }

namespace {
THRONG_CONVERSIONS(SceneryShape, v1::SceneryShape, THRONG_SCENERY_SHAPE_FIELDS)
THRONG_CONVERSIONS(Roster, v1::RosterArrays, THRONG_ROSTER_FIELDS)
}  // namespace

THRONG_CONVERSIONS(JoinRequest, v1::JoinRequest, THRONG_JOIN_REQUEST_FIELDS)
THRONG_CONVERSIONS(JoinReply, v1::JoinReply, THRONG_JOIN_REPLY_FIELDS)
THRONG_CONVERSIONS(Command, v1::Command, THRONG_COMMAND_FIELDS)
THRONG_CONVERSIONS(Snapshot, v1::Snapshot, THRONG_SNAPSHOT_FIELDS)
THRONG_CONVERSIONS(MatchInfo, v1::MatchInfo, THRONG_MATCH_INFO_FIELDS)
THRONG_CONVERSIONS(ParamUpdate, v1::ParamUpdate, THRONG_PARAM_UPDATE_FIELDS)
THRONG_CONVERSIONS(ParamReply, v1::ParamReply, THRONG_PARAM_REPLY_FIELDS)
THRONG_CONVERSIONS(ServerStats, v1::ServerStats, THRONG_SERVER_STATS_FIELDS)
THRONG_CONVERSIONS(ContactPairs, v1::ContactPairs, THRONG_CONTACT_PAIRS_FIELDS)
THRONG_CONVERSIONS(TickEntry, v1::TickEntry, THRONG_TICK_ENTRY_FIELDS)
THRONG_CONVERSIONS(StandbyRequest, v1::StandbyRequest, THRONG_STANDBY_REQUEST_FIELDS)
THRONG_CONVERSIONS(StandbySync, v1::StandbySync, THRONG_STANDBY_SYNC_FIELDS)
THRONG_CONVERSIONS(PrimaryClaim, v1::PrimaryClaim, THRONG_PRIMARY_CLAIM_FIELDS)

#undef THRONG_CONVERSIONS
#undef THRONG_FROM_WIRE
#undef THRONG_TO_WIRE

}  // namespace throng::protocol::dds_detail
