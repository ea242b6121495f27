#include "report/all_tables.h"

#include "effects/effects.h"
#include "report/aa_table.h"
#include "report/many_lights_table.h"
#include "report/primary_table.h"
#include "report/tables.h"

namespace hb {

std::string allTablesMarkdown(const nlohmann::json& results) {
  std::string out = thesisTablesMarkdown(results);
  auto add = [&](const std::string& table) {
    if (!table.empty()) out += "\n" + table;
  };
  add(primaryTableMarkdown(results));
  add(aaTableMarkdown(results));
  for (const EffectDef* e : allEffects())
    if (e->table) add(e->table(results));
  add(manyLightsTableMarkdown(results));
  return out;
}

}  // namespace hb
