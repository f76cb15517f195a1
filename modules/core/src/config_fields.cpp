#include "rbcp/core/config_fields.h"

namespace rbcp {
namespace {

/// A markdown table cell: a '|' would end it.
std::string Cell(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

}  // namespace

int ConfigLoader::NonNegativeInt(const char* key) const {
  const int v = map_.Int(key);
  if (v < 0) map_.Fail(key, "expected a non-negative integer, got " + std::to_string(v));
  return v;
}

std::string ConfigTable(const ConfigDescription& description) {
  std::string text = "| key | unit | bounds | default | meaning |\n|---|---|---|---|---|\n";
  for (const ConfigField& f : description.fields) {
    text += "| `" + f.key + "` | " + Cell(f.unit) + " | " + Cell(f.bounds) + " | " +
            (f.value.empty() ? "" : "`" + f.value + "`") + " | " + Cell(f.meaning) + " |\n";
  }
  if (!description.rules.empty()) {
    text += "\nAnd between keys:\n\n";
    for (const ConfigRule& r : description.rules) text += "- `" + r.key + "`: " + Cell(r.expected) + "\n";
  }
  return text;
}

}  // namespace rbcp
