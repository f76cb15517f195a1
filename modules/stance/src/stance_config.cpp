#include "rbcp/stance/stance_config.h"

namespace rbcp {

StanceRules StanceRules::LoadFromDir(const std::string& config_dir) {
  StanceRules rules;
  rules.config = StanceConfig::LoadFile(config_dir + "/stance.yaml");
  rules.friction = EquilibriumConfig::LoadFile(config_dir + "/equilibrium.yaml").friction;
  return rules;
}

}  // namespace rbcp
