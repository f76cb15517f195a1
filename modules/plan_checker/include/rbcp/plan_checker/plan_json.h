#pragma once
/// The JSON form of a contact plan, as printed by plan_scenario and read by check_plan.
///
/// A plan is an array of states, world frame, metres and radians:
/// @code
/// [{"base": {"position": [x, y, z], "rpy": [roll, pitch, yaw]},
///   "joints": [12 values: LF, RF, LH, RH x (HAA, HFE, KFE)],
///   "feet": [{"leg": "LF", "position": [x, y, z], "normal": [x, y, z]}, ... one per leg],
///   "moving_leg": "LF" | "RF" | "LH" | "RH" | null},   // null for the first state
///  ...]
/// @endcode
/// A foot's position is its contact point on the surface and its normal the surface normal.
/// Numbers are written with the shortest representation that reads back to the same double,
/// so ContactPlanFromJson(ContactPlanToJson(plan)) reproduces the plan bit for bit.

#include <nlohmann/json_fwd.hpp>

#include <string>

#include "rbcp/core/contact_plan.h"

namespace rbcp {

/// Version of the JSON documents the programs print (plan_scenario, check_plan, anymal_sim --plan,
/// run_log, scene_json; see docs/json_schema.md). Raised when a key changes meaning or goes away;
/// new keys keep it.
inline constexpr int kJsonSchemaVersion = 1;

/// Adds "schema_version" (kJsonSchemaVersion) and "joint_names" (the URDF names of the 12 joints,
/// in the order of every joint array: LF, RF, LH, RH x HAA, HFE, KFE) to a document.
void AddSchemaKeys(nlohmann::json& document);

/// The plan as a JSON array of states; feet are written in the order LF, RF, LH, RH.
/// Throws InputError when a state's moving_leg is neither -1 nor a leg index.
nlohmann::json ContactPlanToJson(const ContactPlan& plan);

/// Reads a JSON array of states strictly: every key above is required, no other key is accepted,
/// numbers must be finite, each leg appears exactly once in "feet" (in any order). Throws
/// InputError "state 3: 'joints': expected an array of 12 numbers, got an array of 11 elements".
ContactPlan ContactPlanFromJson(const nlohmann::json& states);

/// Reads either a bare array of states or an object holding the array under "states" (the
/// output of plan_scenario; its other keys are ignored).
ContactPlan ContactPlanFromJsonDocument(const nlohmann::json& document);

/// Reads a JSON file ("-" = standard input) with ParseContactPlanJson. Throws InputError naming
/// the file for an unreadable file, malformed JSON or a malformed plan.
ContactPlan LoadContactPlanFile(const std::string& path);

/// Parses JSON text with ContactPlanFromJsonDocument. Throws InputError starting with `name` for
/// malformed JSON or a malformed plan.
ContactPlan ParseContactPlanJson(const std::string& text, const std::string& name);

}  // namespace rbcp
