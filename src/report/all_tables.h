// tables.md: every table a results file has rows for — the thesis's Tables 5.1/5.2, the primary-
// visibility table, each effect's own table (effects/effect.h EffectDef::table, in effect order),
// the many-lights table — as `sweep` writes it and `tables` prints it.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace hb {

// Throws InputError when `results` is not a results file.
std::string allTablesMarkdown(const nlohmann::json& results);

}  // namespace hb
