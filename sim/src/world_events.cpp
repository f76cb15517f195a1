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
  ev.t = e.Double("t");
  if (!(ev.t >= 0.0)) e.Fail("t", "expected a simulated time >= 0 [s], got " + FixedNumber(ev.t, 3));
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
    if ((ev.box.size.array() <= 0.0).any()) m.Fail("size", "expected three positive lengths [m]");
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
    if (!(ev.duration_s > 0.0)) m.Fail("duration", "expected a positive duration [s], got " + FixedNumber(ev.duration_s, 3));
    m.RejectUnknownKeys();
  } else if (kind == "goal") {
    ev.kind = WorldEvent::Kind::kGoal;
    ev.goal = ReadBasePose(e.Map("goal"));
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
  YAML::Node node;
  try {
    node = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(where + ": not valid YAML: " + e.what());
  }
  const YamlMap root(node, where);
  std::vector<WorldEvent> events;
  for (const YamlMap& e : root.MapList("events")) events.push_back(ReadEvent(e, events));
  root.RejectUnknownKeys();
  std::stable_sort(events.begin(), events.end(), [](const WorldEvent& a, const WorldEvent& b) { return a.t < b.t; });
  // A box is removed after it was added.
  for (std::size_t i = 0; i < events.size(); ++i) {
    if (events[i].kind != WorldEvent::Kind::kRemoveBox) continue;
    const bool before = std::any_of(events.begin(), events.begin() + static_cast<std::ptrdiff_t>(i), [&](const WorldEvent& o) {
      return o.kind == WorldEvent::Kind::kAddBox && o.name == events[i].name;
    });
    if (!before) {
      throw InputError(where + ": box '" + events[i].name + "' is removed at " + FixedNumber(events[i].t, 2) +
                       " s, but no earlier event adds it");
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
