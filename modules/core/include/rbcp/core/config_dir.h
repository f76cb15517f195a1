#pragma once
/// Where the programs find their configuration (robots/, scenarios/ and the per-process yaml).

#include <string>

namespace rbcp {

/// The config folder: $RBCP_CONFIG_DIR if set; else, for a program installed in PREFIX/bin,
/// PREFIX/share/rbcp/config (what `cmake --install` writes); else the config/ of the checkout
/// this library was built from.
std::string DefaultConfigDir();

}  // namespace rbcp
