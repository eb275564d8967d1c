#pragma once
// Field-by-field conversions between the plain structs of messages.h and the fastddsgen types.
// from_idl takes the sample by rvalue and moves its strings and arrays out. Enum values travel as
// octets and are copied as they are: a value this build does not know survives conversion and the
// receiver decides (the server validates every client input).
#include "throng/protocol/messages.h"
#include "throng.h"

namespace throng::protocol::dds_detail {

v1::JoinRequest to_idl(const JoinRequest& m);
v1::JoinReply to_idl(const JoinReply& m);
v1::Command to_idl(const Command& m);
v1::Snapshot to_idl(const Snapshot& m);
v1::MatchInfo to_idl(const MatchInfo& m);
v1::ParamUpdate to_idl(const ParamUpdate& m);
v1::ParamReply to_idl(const ParamReply& m);
v1::ServerStats to_idl(const ServerStats& m);
v1::ContactPairs to_idl(const ContactPairs& m);
v1::TickEntry to_idl(const TickEntry& m);
v1::StandbyRequest to_idl(const StandbyRequest& m);
v1::StandbySync to_idl(const StandbySync& m);
v1::PrimaryClaim to_idl(const PrimaryClaim& m);

JoinRequest from_idl(v1::JoinRequest&& s);
JoinReply from_idl(v1::JoinReply&& s);
Command from_idl(v1::Command&& s);
Snapshot from_idl(v1::Snapshot&& s);
MatchInfo from_idl(v1::MatchInfo&& s);
ParamUpdate from_idl(v1::ParamUpdate&& s);
ParamReply from_idl(v1::ParamReply&& s);
ServerStats from_idl(v1::ServerStats&& s);
ContactPairs from_idl(v1::ContactPairs&& s);
TickEntry from_idl(v1::TickEntry&& s);
StandbyRequest from_idl(v1::StandbyRequest&& s);
StandbySync from_idl(v1::StandbySync&& s);
PrimaryClaim from_idl(v1::PrimaryClaim&& s);

}  // namespace throng::protocol::dds_detail
