#include "rbcp/plan_checker/plan_json.h"

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>

#include "rbcp/core/error.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp {
namespace {

using nlohmann::json;

/// "an array of 11 elements", "a string (\"x\")", "an object", "null", ... for error messages.
std::string Describe(const json& value) {
  switch (value.type()) {
    case json::value_t::array:
      return "an array of " + std::to_string(value.size()) + (value.size() == 1 ? " element" : " elements");
    case json::value_t::object:
      return "an object";
    case json::value_t::string:
      return "a string (" + value.dump() + ")";
    case json::value_t::boolean:
      return std::string("a boolean (") + (value.get<bool>() ? "true" : "false") + ")";
    case json::value_t::null:
      return "null";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float:
      return "a number (" + value.dump() + ")";
    default:
      return value.type_name();
  }
}

/// Reads one state; every error names the state and the key path.
class StateReader {
 public:
  explicit StateReader(std::size_t index) : where_("state " + std::to_string(index)) {}

  [[noreturn]] void Fail(const std::string& key, const std::string& expected, const json& got) const {
    throw InputError(where_ + ": " + (key.empty() ? "" : key + ": ") + "expected " + expected + ", got " +
                     Describe(got));
  }

  /// `value` itself, after checking that it is an object.
  const json& Object(const json& value, const std::string& path) const {
    if (!value.is_object()) Fail(path, "an object", value);
    return value;
  }

  /// Rejects missing and unknown keys of an object.
  /// Every key of `keys` present, and no other key than those and the `optional` ones.
  void RequireKeys(const json& object, const std::string& path, const std::vector<std::string>& keys,
                   const std::vector<std::string>& optional = {}) const {
    for (const auto& key : keys) {
      if (!object.contains(key)) {
        throw InputError(where_ + ": " + (path.empty() ? "" : path + ": ") + "expected a key '" + key +
                         "', got an object without it");
      }
    }
    for (const auto& item : object.items()) {
      bool known = false;
      for (const auto& key : keys) known = known || item.key() == key;
      for (const auto& key : optional) known = known || item.key() == key;
      if (!known) {
        std::string list;
        for (const auto& key : keys) list += (list.empty() ? "" : ", ") + key;
        for (const auto& key : optional) list += (list.empty() ? "" : ", ") + key + " (optional)";
        throw InputError(where_ + ": " + (path.empty() ? "" : path + ": ") + "expected only the keys " + list +
                         ", got an unknown key '" + item.key() + "'");
      }
    }
  }

  template <int N>
  Eigen::Matrix<double, N, 1> Numbers(const json& value, const std::string& path) const {
    const std::string expected = "an array of " + std::to_string(N) + " numbers";
    if (!value.is_array() || value.size() != static_cast<std::size_t>(N)) Fail(path, expected, value);
    Eigen::Matrix<double, N, 1> out;
    for (int k = 0; k < N; ++k) {
      const json& element = value[static_cast<std::size_t>(k)];
      if (!element.is_number()) {
        Fail(path + "[" + std::to_string(k) + "]", "a number", element);
      }
      out[k] = element.get<double>();
      if (!std::isfinite(out[k])) Fail(path + "[" + std::to_string(k) + "]", "a finite number", element);
    }
    return out;
  }

  double FiniteNumber(const json& value, const std::string& path) const {
    if (!value.is_number() || !std::isfinite(value.get<double>())) Fail(path, "a finite number", value);
    return value.get<double>();
  }

  Leg LegName(const json& value, const std::string& path) const {
    if (value.is_string()) {
      if (auto leg = LegFromName(value.get<std::string>())) return *leg;
    }
    Fail(path, "one of \"LF\", \"RF\", \"LH\", \"RH\"", value);
  }

  WholeBodyState Read(const json& value) const {
    WholeBodyState state;
    Object(value, "");
    RequireKeys(value, "", {"base", "joints", "feet", "moving_leg"}, {"swing", "timing"});

    const json& base = Object(value["base"], "'base'");
    RequireKeys(base, "'base'", {"position", "rpy"});
    state.base_position = Numbers<3>(base["position"], "'base'.'position'");
    state.base_rpy = Numbers<3>(base["rpy"], "'base'.'rpy'");

    state.joints = Numbers<12>(value["joints"], "'joints'");

    const json& feet = value["feet"];
    if (!feet.is_array() || feet.size() != static_cast<std::size_t>(kNumLegs)) {
      Fail("'feet'", "an array of 4 feet", feet);
    }
    std::array<bool, kNumLegs> seen{};
    for (std::size_t k = 0; k < feet.size(); ++k) {
      const std::string path = "'feet'[" + std::to_string(k) + "]";
      const json& foot = Object(feet[k], path);
      RequireKeys(foot, path, {"leg", "position", "normal"});
      const Leg leg = LegName(foot["leg"], path + ".'leg'");
      if (seen[static_cast<std::size_t>(Index(leg))]) {
        Fail(path + ".'leg'", "each of LF, RF, LH, RH once", foot["leg"]);
      }
      seen[static_cast<std::size_t>(Index(leg))] = true;
      FootContact& contact = state.feet[static_cast<std::size_t>(Index(leg))];
      contact.position = Numbers<3>(foot["position"], path + ".'position'");
      contact.normal = Numbers<3>(foot["normal"], path + ".'normal'");
    }

    const json& moving = value["moving_leg"];
    state.moving_leg = moving.is_null() ? -1 : Index(LegName(moving, "'moving_leg'"));
    if (value.contains("swing") && !value["swing"].is_null()) {
      const json& swing = Object(value["swing"], "'swing'");
      RequireKeys(swing, "'swing'", {"apex_z", "bow"});
      state.swing_apex_z = FiniteNumber(swing["apex_z"], "'swing'.'apex_z'");
      state.swing_bow = Numbers<2>(swing["bow"], "'swing'.'bow'");
    }
    if (value.contains("timing") && !value["timing"].is_null()) {
      const json& timing = Object(value["timing"], "'timing'");
      RequireKeys(timing, "'timing'", {"lift_off_s", "touch_down_s"});
      state.lift_off_s = FiniteNumber(timing["lift_off_s"], "'timing'.'lift_off_s'");
      state.touch_down_s = FiniteNumber(timing["touch_down_s"], "'timing'.'touch_down_s'");
    }
    return state;
  }

 private:
  std::string where_;
};

json Vector3Json(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

}  // namespace

json ContactPlanToJson(const ContactPlan& plan) {
  json states = json::array();
  for (std::size_t i = 0; i < plan.states.size(); ++i) {
    const WholeBodyState& state = plan.states[i];
    json joints = json::array();
    for (int j = 0; j < state.joints.size(); ++j) joints.push_back(state.joints[j]);
    json feet = json::array();
    for (Leg leg : kAllLegs) {
      const FootContact& foot = state.feet[static_cast<std::size_t>(Index(leg))];
      feet.push_back(json{{"leg", std::string(LegName(leg))},
                          {"position", Vector3Json(foot.position)},
                          {"normal", Vector3Json(foot.normal)}});
    }
    json moving_leg;  // null
    if (state.moving_leg >= 0 && state.moving_leg < kNumLegs) {
      moving_leg = std::string(LegName(kAllLegs[static_cast<std::size_t>(state.moving_leg)]));
    } else if (state.moving_leg != -1) {
      throw InputError("state " + std::to_string(i) + ": moving_leg: expected -1 or a leg index in [0, 3], got " +
                       std::to_string(state.moving_leg));
    }
    json out{{"base", json{{"position", Vector3Json(state.base_position)}, {"rpy", Vector3Json(state.base_rpy)}}},
             {"joints", std::move(joints)},
             {"feet", std::move(feet)},
             {"moving_leg", std::move(moving_leg)}};
    if (state.HasSwing()) {
      out["swing"] = json{{"apex_z", state.swing_apex_z}, {"bow", json::array({state.swing_bow.x(), state.swing_bow.y()})}};
    }
    if (state.HasTiming()) out["timing"] = json{{"lift_off_s", state.lift_off_s}, {"touch_down_s", state.touch_down_s}};
    states.push_back(std::move(out));
  }
  return states;
}

ContactPlan ContactPlanFromJson(const json& states) {
  if (!states.is_array()) {
    throw InputError("contact plan: expected an array of states, got " + Describe(states));
  }
  ContactPlan plan;
  plan.states.reserve(states.size());
  for (std::size_t i = 0; i < states.size(); ++i) plan.states.push_back(StateReader(i).Read(states[i]));
  if (auto bad = TimingProblem(plan)) throw InputError("contact plan: timing: " + *bad);
  return plan;
}

ContactPlan ContactPlanFromJsonDocument(const json& document) {
  if (document.is_array()) return ContactPlanFromJson(document);
  if (document.is_object()) {
    if (!document.contains("states")) {
      throw InputError("contact plan: expected an array of states or an object with a key 'states', got an "
                       "object without 'states'");
    }
    const json& states = document["states"];
    if (!states.is_array()) {
      throw InputError("contact plan: 'states': expected an array of states, got " + Describe(states));
    }
    return ContactPlanFromJson(states);
  }
  throw InputError("contact plan: expected an array of states or an object with a key 'states', got " +
                   Describe(document));
}

ContactPlan LoadContactPlanFile(const std::string& path) {
  const std::string name = path == "-" ? std::string("standard input") : path;
  std::string text;
  if (path == "-") {
    text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
  } else {
    if (std::filesystem::is_directory(path)) throw InputError(name + ": expected a JSON file, got a directory");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(name + ": cannot open the file for reading");
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) throw InputError(name + ": cannot read the file");
    text = buffer.str();
  }
  return ParseContactPlanJson(text, name);
}

ContactPlan ParseContactPlanJson(const std::string& text, const std::string& name) {
  json document;
  try {
    document = json::parse(text);
  } catch (const json::exception& e) {  // parse_error, and out_of_range for a number beyond double
    throw InputError(name + ": malformed JSON: " + e.what());
  }
  try {
    return ContactPlanFromJsonDocument(document);
  } catch (const InputError& e) {
    throw InputError(name + ": " + e.what());
  }
}

void AddSchemaKeys(nlohmann::json& document) {
  document["schema_version"] = kJsonSchemaVersion;
  json names = json::array();
  for (int j = 0; j < kNumJoints; ++j) names.push_back(JointName(j));
  document["joint_names"] = std::move(names);
}

}  // namespace rbcp
