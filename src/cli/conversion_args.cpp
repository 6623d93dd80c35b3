#include "cli/conversion_args.h"

#include <limits>
#include <type_traits>
#include <variant>

#include "api/option_table.h"

namespace ahd::cli {

void add_input_options(CLI::App* c, BakeInput* a) {
  for (const BakeInputOption& o : bake_input_options()) {
    if (auto s = std::get_if<std::string BakeInput::*>(&o.field)) {
      c->add_option(o.flag, a->**s, o.help);
    } else if (auto i = std::get_if<int BakeInput::*>(&o.field)) {
      c->add_option(o.flag, a->**i, o.help)->check(CLI::Range(o.min_value, std::numeric_limits<int>::max()));
    } else {
      c->add_flag(o.flag, a->*std::get<bool BakeInput::*>(o.field), o.help);
    }
  }
}

void add_conversion_options(CLI::App* c, ConversionArgs* a, bool fit) {
  for (const OptionRow& r : option_table()) {
    if (!r.spec.flag || (r.spec.fit_only && !fit)) continue;
    CLI::Option* flag = nullptr;
    if (r.type == OptionType::Enum) {
      std::string& v = a->enums[r.name];
      v = r.spec.cli_default ? r.spec.cli_default : r.text(a->options);
      std::vector<std::string> names;
      for (const OptionEnumValue& e : r.values) names.push_back(e.name);
      flag = c->add_option(r.spec.flag, v, r.spec.help)->check(CLI::IsMember(names));
    } else if (r.spec.negated) {
      flag = c->add_flag(r.spec.flag, a->negated[r.name], r.spec.help);
    } else {
      std::visit(
          [&](auto m) {
            if constexpr (!std::is_same_v<decltype(m), std::monostate>) {
              if constexpr (std::is_same_v<decltype(m), bool ConversionOptions::*>)
                flag = c->add_flag(r.spec.flag, a->options.*m, r.spec.help);
              else
                flag = c->add_option(r.spec.flag, a->options.*m, r.spec.help);
            }
          },
          r.member);
    }
    if (flag && r.spec.non_negative) flag->check(CLI::NonNegativeNumber);
  }
  c->add_flag("-q,--quiet", a->quiet, "Print nothing on success");
}

ConversionOptions conversion_options(const ConversionArgs& a) {
  ConversionOptions o = a.options;
  for (const OptionRow& r : option_table()) {
    if (auto e = a.enums.find(r.name); e != a.enums.end()) r.parse(o, e->second);
    if (auto n = a.negated.find(r.name); n != a.negated.end() && n->second) r.parse(o, "0");
  }
  return o;
}

}  // namespace ahd::cli
