#include "rbcp/sim/world_events.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/core/yaml_reader.h"

namespace rbcp::sim {
namespace {

std::string Xyz(const Eigen::Vector3d& v) {
  return FixedNumber(v.x(), 2) + ", " + FixedNumber(v.y(), 2) + ", " + FixedNumber(v.z(), 2);
}

WorldEvent ReadEvent(const YamlMap& e, const std::vector<WorldEvent>& earlier) {
  WorldEvent ev;
  using L = WorldEventLimits;
  ev.t = e.Double("t");
  if (!(ev.t >= 0.0 && ev.t <= L::kMaxTime_s)) {
    e.Fail("t", "expected a simulated time in [0, " + FixedNumber(L::kMaxTime_s, 0) + "] s, got " + FixedNumber(ev.t, 3));
  }
  const auto within_reach = [](const YamlMap& m, const std::string& key, const Eigen::Vector3d& p) {
    if (!(p.allFinite() && p.norm() <= L::kMaxDistance_m)) {
      m.Fail(key, "expected a point within " + FixedNumber(L::kMaxDistance_m, 0) + " m of the origin, got (" + Xyz(p) + ")");
    }
  };
  std::vector<std::string> kinds;
  for (const std::string& k : e.Keys()) {
    if (k != "t") kinds.push_back(k);
  }
  if (kinds.size() != 1) {
    e.Fail("", "expected t and exactly one of add_box, remove_box, push or goal, got " + std::to_string(kinds.size()) +
                   " other keys");
  }
  const std::string& kind = kinds.front();
  if (kind == "add_box") {
    ev.kind = WorldEvent::Kind::kAddBox;
    const YamlMap m = e.Map("add_box");
    ev.name = m.String("name");
    if (ev.name.empty()) m.Fail("name", "expected a name for the box, got an empty string");
    ev.box.size = m.Vector3("size");
    ev.box.position = m.Vector3("position");
    ev.box.rpy = m.Vector3("rpy");
    if (!((ev.box.size.array() > 0.0).all() && (ev.box.size.array() <= L::kMaxBoxSize_m).all())) {
      m.Fail("size", "expected three lengths in (0, " + FixedNumber(L::kMaxBoxSize_m, 0) + "] m, got (" + Xyz(ev.box.size) + ")");
    }
    within_reach(m, "position", ev.box.position);
    if (!ev.box.rpy.allFinite()) m.Fail("rpy", "expected finite angles [rad]");
    m.RejectUnknownKeys();
    for (const WorldEvent& o : earlier) {
      if (o.kind == WorldEvent::Kind::kAddBox && o.name == ev.name) m.Fail("name", "box '" + ev.name + "' is added twice");
    }
  } else if (kind == "remove_box") {
    ev.kind = WorldEvent::Kind::kRemoveBox;
    ev.name = e.String("remove_box");  // added before it is removed: checked once the events are in time order
  } else if (kind == "push") {
    ev.kind = WorldEvent::Kind::kPush;
    const YamlMap m = e.Map("push");
    ev.force_W = m.Vector3("force");
    ev.duration_s = m.Double("duration");
    if (!(ev.duration_s > 0.0 && ev.duration_s <= L::kMaxPushDuration_s)) {
      m.Fail("duration", "expected a duration in (0, " + FixedNumber(L::kMaxPushDuration_s, 0) + "] s, got " +
                             FixedNumber(ev.duration_s, 3));
    }
    if (!(ev.force_W.allFinite() && ev.force_W.norm() <= L::kMaxPush_N)) {
      m.Fail("force", "expected at most " + FixedNumber(L::kMaxPush_N, 0) + " N, got (" + Xyz(ev.force_W) + ")");
    }
    m.RejectUnknownKeys();
  } else if (kind == "goal") {
    ev.kind = WorldEvent::Kind::kGoal;
    const YamlMap m = e.Map("goal");
    ev.goal = ReadBasePose(m);
    within_reach(m, "position", Eigen::Vector3d(ev.goal.position.x(), ev.goal.position.y(), 0.0));
    if (!std::isfinite(ev.goal.yaw)) m.Fail("yaw", "expected a finite heading [rad]");
  } else {
    e.Fail(kind, "unknown event (expected add_box, remove_box, push or goal)");
  }
  e.RejectUnknownKeys();
  return ev;
}

}  // namespace

std::string WorldEvent::Describe() const {
  std::ostringstream os;
  switch (kind) {
    case Kind::kAddBox:
      os << "add box '" << name << "' (" << FixedNumber(box.size.x(), 2) << " x " << FixedNumber(box.size.y(), 2) << " x "
         << FixedNumber(box.size.z(), 2) << " m at " << Xyz(box.position) << ")";
      break;
    case Kind::kRemoveBox: os << "remove box '" << name << "'"; break;
    case Kind::kPush:
      os << "push the base with " << FixedNumber(force_W.norm(), 1) << " N (" << Xyz(force_W) << ") for "
         << FixedNumber(duration_s, 2) << " s";
      break;
    case Kind::kGoal:
      os << "new goal (" << FixedNumber(goal.position.x(), 2) << ", " << FixedNumber(goal.position.y(), 2) << "), yaw "
         << FixedNumber(goal.yaw, 2);
      break;
  }
  return os.str();
}

std::vector<WorldEvent> ParseWorldEvents(const std::string& yaml_text, const std::string& where) {
  const YamlMap root = YamlMap::Parse(yaml_text, where);
  std::vector<WorldEvent> events;
  const std::vector<YamlMap> listed = root.MapList("events");
  if (listed.size() > WorldEventLimits::kMaxEvents) {
    root.Fail("events", "expected at most " + std::to_string(WorldEventLimits::kMaxEvents) + " events, got " +
                            std::to_string(listed.size()));
  }
  for (const YamlMap& e : listed) events.push_back(ReadEvent(e, events));
  root.RejectUnknownKeys();
  std::stable_sort(events.begin(), events.end(), [](const WorldEvent& a, const WorldEvent& b) { return a.t < b.t; });
  // In time order: a box is removed while it is in the world, and the world holds a bounded
  // number of the events' boxes.
  std::vector<std::string> present;
  for (const WorldEvent& e : events) {
    if (e.kind == WorldEvent::Kind::kAddBox) {
      present.push_back(e.name);
      if (present.size() > WorldEventLimits::kMaxBoxes) {
        throw InputError(where + ": " + std::to_string(present.size()) + " boxes of the events would be in the world at " +
                         FixedNumber(e.t, 2) + " s, at most " + std::to_string(WorldEventLimits::kMaxBoxes));
      }
    } else if (e.kind == WorldEvent::Kind::kRemoveBox) {
      const auto it = std::find(present.begin(), present.end(), e.name);
      if (it == present.end()) {
        throw InputError(where + ": box '" + e.name + "' is removed at " + FixedNumber(e.t, 2) +
                         " s, but it is not in the world then (never added, or removed before)");
      }
      present.erase(it);
    }
  }
  return events;
}

std::vector<WorldEvent> LoadWorldEvents(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the events file");
  std::ostringstream text;
  text << in.rdbuf();
  return ParseWorldEvents(text.str(), path);
}

}  // namespace rbcp::sim
