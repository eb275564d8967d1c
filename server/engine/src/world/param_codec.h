#pragma once
// Binary encoding of the parameter-side state a checkpoint carries: per-object parameter records,
// the push policy (the operator may replace it at run time) and the groups (morale is dynamic).
// Field by field, little-endian (core/byte_io.h); the layout is in world/CHECKPOINT.md.
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "throng/core/byte_io.h"
#include "throng/params/group_table.h"
#include "throng/params/object_params.h"
#include "throng/params/push_policy.h"

namespace throng::detail {

// Bytes of one ObjectParams record (fixed size: a record array is one block of n * this), with
// and without its object id.
inline constexpr std::size_t kParamsRecordBytes = 120;
inline constexpr std::size_t kParamsRecordBytesWithoutId = 116;

// Whether a record carries its object id: bodies' records leave it out (world state version 3),
// because a body's object id is its ObjectId, which the slot table already names.
enum class ObjectIdField : std::uint8_t { kept, left_out };

// With a non-empty order, record i written is records[order[i]] (bodies whose records still wait
// for a re-sort's order: World::Impl::params_order).
void put_params(ByteWriter& w, std::span<const params::ObjectParams> records, ObjectIdField ids = ObjectIdField::kept,
                std::span<const std::uint32_t> order = {});
// Reads exactly n records; categorical values out of range throw CheckpointError. With left_out
// the records' object_id is 0, for the caller to set.
void get_params(ByteReader& r, std::size_t n, std::vector<params::ObjectParams>& out, const char* what,
                ObjectIdField ids = ObjectIdField::kept);

void put_policy(ByteWriter& w, const params::PushPolicy& policy);
// Validates through PushPolicy's constructor; its error becomes a CheckpointError.
params::PushPolicy get_policy(ByteReader& r);

// Groups as (id, attributes) in ascending id order; the morale thresholds are the table's (scene).
void put_groups(ByteWriter& w, const params::GroupTable& groups);
std::vector<std::pair<std::uint32_t, params::Group>> get_groups(ByteReader& r);

}  // namespace throng::detail
