#include "api/option_table.h"

#include <cstdio>

#include "containers/sha256.h"
#include "core/error.h"
#include "core/option_enums.h"

namespace ahd {

namespace {

// The defaults: the public struct's member initialisers. Static, so that the C defaults of text
// options can point into it for the life of the program.
const ConversionOptions& defaults() {
  static const ConversionOptions d;
  return d;
}

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

template <typename M>
size_t offset_of(M ahd_options::*cm) {
  static const ahd_options probe{};
  return size_t(reinterpret_cast<const char*>(&(probe.*cm)) - reinterpret_cast<const char*>(&probe));
}

OptionRow base(const char* name, OptionType type, const OptionSpec& spec) {
  OptionRow r;
  r.name = name;
  r.type = type;
  r.spec = spec;
  return r;
}

std::string choices(const std::vector<OptionEnumValue>& values) {
  std::string s;
  for (size_t i = 0; i < values.size(); ++i)
    s += std::string(i == 0 ? "" : i + 1 == values.size() ? " or " : ", ") + values[i].name;
  return s;
}

[[noreturn]] void bad_value(const OptionRow& r, const std::string& v) {
  const std::string what = r.spec.flag ? r.spec.flag : r.name;
  if (r.type == OptionType::Enum) throw Error(what + " must be " + choices(r.values) + " (got '" + v + "')");
  throw Error(what + ": invalid value '" + v + "'");
}

OptionRow text_option(const char* name, std::string ConversionOptions::*m, const char* ahd_options::*cm, OptionSpec spec) {
  OptionRow r = base(name, OptionType::Text, spec);
  r.member = m;
  r.c_offset = offset_of(cm), r.c_size = sizeof(const char*);
  r.text = [m](const ConversionOptions& o) { return o.*m; };
  r.key_text = [m, key = spec.key](const ConversionOptions& o) {
    const std::string& s = o.*m;
    if (key == KeyForm::Hash) return sha256_hex(reinterpret_cast<const uint8_t*>(s.data()), s.size());
    return key == KeyForm::None ? std::string() : s;
  };
  r.parse = [m](ConversionOptions& o, const std::string& v) { o.*m = v; };
  r.from_c = [m, cm](const ahd_options& c, ConversionOptions& o) {
    if (c.*cm) o.*m = c.*cm;  // NULL: the default
  };
  r.c_default = [m, cm](ahd_options& c) { c.*cm = (defaults().*m).empty() ? nullptr : (defaults().*m).c_str(); };
  r.change = [m](ConversionOptions& o) { o.*m += "x"; };
  return r;
}

OptionRow bool_option(const char* name, bool ConversionOptions::*m, int ahd_options::*cm, OptionSpec spec) {
  OptionRow r = base(name, OptionType::Bool, spec);
  r.member = m;
  r.c_offset = offset_of(cm), r.c_size = sizeof(int);
  r.text = [m](const ConversionOptions& o) { return std::to_string(int(o.*m)); };
  r.key_text = [m, key = spec.key](const ConversionOptions& o) {
    return key == KeyForm::None ? std::string() : std::to_string(int(o.*m));
  };
  r.parse = [m, r](ConversionOptions& o, const std::string& v) {
    if (v == "1" || v == "true") o.*m = true;
    else if (v == "0" || v == "false") o.*m = false;
    else bad_value(r, v);
  };
  r.from_c = [m, cm](const ahd_options& c, ConversionOptions& o) { o.*m = c.*cm != 0; };
  r.c_default = [m, cm](ahd_options& c) { c.*cm = int(defaults().*m); };
  r.change = [m](ConversionOptions& o) { o.*m = !(o.*m); };
  return r;
}

OptionRow int_option(const char* name, int ConversionOptions::*m, int ahd_options::*cm, OptionSpec spec) {
  OptionRow r = base(name, OptionType::Int, spec);
  r.member = m;
  r.c_offset = offset_of(cm), r.c_size = sizeof(int);
  r.text = [m](const ConversionOptions& o) { return std::to_string(o.*m); };
  r.key_text = [m, key = spec.key](const ConversionOptions& o) {
    return key == KeyForm::None ? std::string() : std::to_string(o.*m);
  };
  r.parse = [m, r](ConversionOptions& o, const std::string& v) {
    size_t used = 0;
    try {
      o.*m = std::stoi(v, &used);
    } catch (const std::exception&) {
      bad_value(r, v);
    }
    if (used != v.size()) bad_value(r, v);
  };
  r.from_c = [m, cm](const ahd_options& c, ConversionOptions& o) { o.*m = c.*cm; };
  r.c_default = [m, cm](ahd_options& c) { c.*cm = defaults().*m; };
  r.change = [m](ConversionOptions& o) { o.*m += 1; };
  return r;
}

OptionRow double_option(const char* name, double ConversionOptions::*m, double ahd_options::*cm, OptionSpec spec) {
  OptionRow r = base(name, OptionType::Double, spec);
  r.member = m;
  r.c_offset = offset_of(cm), r.c_size = sizeof(double);
  r.text = [m](const ConversionOptions& o) { return num(o.*m); };
  r.key_text = [m, key = spec.key](const ConversionOptions& o) { return key == KeyForm::None ? std::string() : num(o.*m); };
  r.parse = [m, r](ConversionOptions& o, const std::string& v) {
    size_t used = 0;
    try {
      o.*m = std::stod(v, &used);
    } catch (const std::exception&) {
      bad_value(r, v);
    }
    if (used != v.size()) bad_value(r, v);
  };
  r.from_c = [m, cm](const ahd_options& c, ConversionOptions& o) { o.*m = c.*cm; };
  r.c_default = [m, cm](ahd_options& c) { c.*cm = defaults().*m; };
  r.change = [m](ConversionOptions& o) { o.*m = o.*m * 1.5 + 0.01; };
  return r;
}

template <typename E, size_t N>
std::vector<OptionEnumValue> enum_values(const std::array<EnumName<E>, N>& t) {
  std::vector<OptionEnumValue> v;
  for (const EnumName<E>& e : t) v.push_back({e.name, e.cpp});
  return v;
}

[[noreturn]] void bad_c_value(const char* name, int v) {
  throw Error(std::string("invalid option ") + name + " = " + std::to_string(v));
}

template <typename E, size_t N>
OptionRow enum_option(const char* name, E ConversionOptions::*m, int ahd_options::*cm, const std::array<EnumName<E>, N>& t,
                      OptionSpec spec) {
  OptionRow r = base(name, OptionType::Enum, spec);
  r.values = enum_values(t);
  r.c_offset = offset_of(cm), r.c_size = sizeof(int);
  r.text = [m, &t](const ConversionOptions& o) { return std::string(enum_name(t, o.*m)); };
  r.key_text = [m, &t, key = spec.key](const ConversionOptions& o) {
    if (key == KeyForm::Name) return std::string(enum_name(t, o.*m));
    return key == KeyForm::None ? std::string() : std::to_string(int(o.*m));
  };
  r.parse = [m, &t, r](ConversionOptions& o, const std::string& v) {
    if (!parse_enum(t, v, &(o.*m))) bad_value(r, v);
  };
  r.from_c = [m, cm, name](const ahd_options& c, ConversionOptions& o) {
    if (c.*cm < 0 || c.*cm >= int(N)) bad_c_value(name, c.*cm);
    o.*m = E(c.*cm);
  };
  r.c_default = [m, cm](ahd_options& c) { c.*cm = int(defaults().*m); };
  r.change = [m](ConversionOptions& o) { o.*m = E((int(o.*m) + 1) % int(N)); };
  return r;
}

// An enumeration that may be unset (C: −1; CLI: ""; key: `unset`).
template <typename E, size_t N>
OptionRow optional_enum_option(const char* name, std::optional<E> ConversionOptions::*m, int ahd_options::*cm,
                               const std::array<EnumName<E>, N>& t, const char* unset, OptionSpec spec) {
  OptionRow r = base(name, OptionType::Enum, spec);
  r.values = enum_values(t);
  r.unset = unset;
  r.c_offset = offset_of(cm), r.c_size = sizeof(int);
  r.text = [m, &t](const ConversionOptions& o) { return o.*m ? std::string(enum_name(t, *(o.*m))) : std::string(); };
  r.key_text = [m, &t, unset, key = spec.key](const ConversionOptions& o) {
    if (key == KeyForm::None) return std::string();
    if (!(o.*m)) return std::string(key == KeyForm::Name ? unset : "-1");
    return key == KeyForm::Name ? std::string(enum_name(t, *(o.*m))) : std::to_string(int(*(o.*m)));
  };
  r.parse = [m, &t, r](ConversionOptions& o, const std::string& v) {
    E e{};
    if (v.empty()) o.*m = std::nullopt;
    else if (parse_enum(t, v, &e)) o.*m = e;
    else bad_value(r, v);
  };
  r.from_c = [m, cm, name](const ahd_options& c, ConversionOptions& o) {
    if (c.*cm < -1 || c.*cm >= int(N)) bad_c_value(name, c.*cm);
    o.*m = c.*cm < 0 ? std::nullopt : std::optional<E>(E(c.*cm));
  };
  r.c_default = [m, cm](ahd_options& c) { c.*cm = defaults().*m ? int(*(defaults().*m)) : -1; };
  r.change = [m](ConversionOptions& o) {
    const int next = o.*m ? int(*(o.*m)) + 1 : 0;
    o.*m = next < int(N) ? std::optional<E>(E(next)) : std::nullopt;
  };
  return r;
}

using CO = ConversionOptions;

std::vector<OptionRow> make_table() {
  std::vector<OptionRow> t;
  // The container first: it is part of the output's naming, as the key has always listed it.
  t.push_back(enum_option("container", &CO::container, &ahd_options::container, kContainerKinds,
                          {.key = KeyForm::Name, .doc = "the container of every plane"}));
  t.push_back(text_option("profile", &CO::profile, &ahd_options::profile,
                          {.flag = "--profile",
                           .help = "Output profile name or .json file (formats/profiles)",
                           .doc = "a standard profile by name (compiled in): `uncompressed`, `uncompressed-rgb`, "
                                  "`pc-bc`, `pc-bc-half`, `pc-bc-quarter`, `packed-float`, `packed-rgb9e5`"}));
  t.push_back(text_option("profile_json", &CO::profile_json, &ahd_options::profile_json,
                          {.key = KeyForm::Hash,
                           .doc = "or, when not empty, a profile definition in the format of `formats/profiles/*.json`"}));
  t.push_back(optional_enum_option(
      "ratio", &CO::ratio, &ahd_options::ratio, kRatioForms, "profile",
      {.flag = "--ratio",
       .help = "Ratio form: luminance (one channel) or rgb (default: the profile's)",
       .fit_only = true,
       .key = KeyForm::Name,
       .doc = "the ratio plane's form; unset (C: −1) the profile's",
       .doc_default = "the profile's"}));
  t.push_back(enum_option(
      "direction_fit", &CO::direction_fit, &ahd_options::direction_fit, kDirectionFits,
      {.flag = "--direction-fit",
       .help = "d and luminance ratio: refined (default: lowest hemisphere error, per texel) or linear (the paper's)",
       .fit_only = true,
       .doc = "d and the luminance ratio for the lowest hemisphere error, texel by texel; `Linear` is the "
              "paper's direction ([fit.md](fit.md))"}));
  t.push_back(enum_option("bc6h_quality", &CO::bc6h_quality, &ahd_options::bc6h_quality, kBc6hQualities,
                          {.flag = "--quality",
                           .help = "BC6H encoder effort: fast, default, high or max",
                           .doc = "BC6H encoder effort, for profiles with BC6H planes ([bc6h.md](bc6h.md))"}));
  t.push_back(int_option("threads", &CO::threads, &ahd_options::threads,
                         {.flag = "--threads",
                          .help = "Worker threads (0 = all)",
                          .key = KeyForm::None,
                          .doc = "the one thread count of every stage; bytes never depend on it",
                          .doc_default = "0 (all)"}));
  t.push_back(double_option("eps", &CO::eps, &ahd_options::eps,
                            {.flag = "--eps",
                             .help = "Smallest stored d_z (the horizon rule)",
                             .fit_only = true,
                             .doc = "the horizon rule, in (0, 1) ([accuracy.md](accuracy.md) \"Choosing ε, the horizon "
                                    "rule\")"}));
  t.push_back(bool_option("closed_loop", &CO::closed_loop, &ahd_options::closed_loop,
                          {.flag = "--open-loop",
                           .help = "Quantise the ratio from the unquantised fit (for comparison)",
                           .negated = true,
                           .doc = "refit the ratio against the decoded direction and I_z"}));
  t.push_back(int_option("levels", &CO::levels, &ahd_options::levels,
                         {.flag = "--levels",
                          .help = "Mip levels to write (0 = full chain)",
                          .fit_only = true,
                          .non_negative = true,
                          .doc = "mip levels written",
                          .doc_default = "0 (full chain)"}));
  t.push_back(bool_option("coverage_plane", &CO::coverage_plane, &ahd_options::coverage_plane,
                          {.flag = "--coverage-plane",
                           .help = "Also write OUT.coverage.<ext>: R8, 255 where a chart covers the texel",
                           .fit_only = true,
                           .doc = "also an R8 coverage plane"}));
  t.push_back(enum_option(
      "direction", &CO::direction, &ahd_options::direction, kDirectionPlanes,
      {.flag = "--direction",
       .help = "Direction and ratio planes: auto (drop them when I_z alone is within --ambient-threshold of the SH), "
               "keep, drop",
       .doc = "`Auto` drops the direction and ratio planes when I_z alone is enough"}));
  t.push_back(double_option("ambient_threshold", &CO::ambient_threshold, &ahd_options::ambient_threshold,
                            {.flag = "--ambient-threshold",
                             .help = "auto: largest relative RMSE p99 of I_z alone vs the SH that drops the direction "
                                     "planes",
                             .non_negative = true,
                             .doc = "`Auto`: the largest relative RMSE p99 of I_z alone that drops them"}));
  t.push_back(bool_option("zstd", &CO::zstd, &ahd_options::zstd,
                          {.flag = "--zstd", .help = "Zstandard supercompression (KTX2)",
                           .doc = "KTX2 Zstandard supercompression"}));
  t.push_back(bool_option("plane_metadata", &CO::plane_metadata, &ahd_options::plane_metadata,
                          {.flag = "--strict-ktx",
                           .help = "No ahd.* key/values in KTX2 planes (the manifest has them), so `ktx validate -e` "
                                   "passes",
                           .negated = true,
                           .doc = "`ahd.*` key/values in each KTX2 plane (see below)"}));
  t.push_back(enum_option(
      "measure", &CO::measure, &ahd_options::measure, kMeasures,
      {.flag = "--measure",
       .help = "Error diagnostics: off, estimate (a fixed sample of texels; default) or full (every texel, every "
               "level, the unconstrained and open-loop baselines)",
       .cli_default = "estimate",  // the command prints an error estimate; the library measures nothing unless asked
       .doc = "error diagnostics in the report: none, a fixed sample of texels, or every texel and level with "
              "the baselines (the command's default is `estimate`)"}));
  t.push_back(double_option("iz_scale", &CO::iz_scale, &ahd_options::iz_scale,
                            {// The command's --iz-scale also takes E, E/pi and the input's own scale (cook).
                             .key = KeyForm::ValueIfSet,
                             .doc = "stored I_z = `iz_scale` × E (1/π: E/π, what most engines store); recorded in "
                                    "the manifest and the planes; the cook also takes 0, the input's own scale "
                                    "([godot.md](godot.md) \"Irradiance scale\")"}));
  t.push_back(bool_option("stable_names", &CO::stable_names, &ahd_options::stable_names,
                          {.flag = "--stable-names",
                           .help = "Plane files NAME.<plane>.<ext> without the content hash, for engines that "
                                   "refer to them by name (docs/asset-cook.md)",
                           .key = KeyForm::ValueIfSet,
                           .doc = "plane files named `NAME.<plane>.<ext>`, without the content hash, for engines "
                                  "that refer to them by name ([asset-cook.md](asset-cook.md) \"Stable names for "
                                  "engines\")"}));
  return t;
}

std::string docs_default(const OptionRow& r) {
  if (r.spec.doc_default) return r.spec.doc_default;
  const std::string v = r.text(defaults());
  switch (r.type) {
    case OptionType::Text: return v.empty() ? "empty" : "`\"" + v + "\"`";
    case OptionType::Bool: return v == "1" ? "true" : "false";
    case OptionType::Enum:
      for (const OptionEnumValue& e : r.values)
        if (v == e.name) return std::string("`") + e.cpp + "`";
      return v;
    default: {
      char b[40];
      std::snprintf(b, sizeof b, "%g", std::stod(v));
      return b;
    }
  }
}

}  // namespace

bool option_in_key(const OptionRow& r, const ConversionOptions& o) {
  if (r.spec.key == KeyForm::None) return false;
  return r.spec.key != KeyForm::ValueIfSet || r.text(o) != r.text(defaults());
}

const std::vector<OptionRow>& option_table() {
  static const std::vector<OptionRow> t = make_table();
  return t;
}

const OptionRow& option_row(const std::string& name) {
  for (const OptionRow& r : option_table())
    if (name == r.name) return r;
  throw Error("no conversion option '" + name + "'");
}

std::string options_docs_table() {
  std::string t = "| option | default | command-line flag | meaning |\n|---|---|---|---|\n";
  for (const OptionRow& r : option_table()) {
    std::string values;
    if (r.type == OptionType::Enum) {
      for (const OptionEnumValue& e : r.values) values += std::string(values.empty() ? "" : ", ") + "`" + e.cpp + "`";
      values = " (" + values + ")";
    }
    std::string flag = r.spec.flag ? std::string("`") + r.spec.flag + "`" : "–";
    if (r.spec.negated) flag += " (sets it false)";
    t += std::string("| `") + r.name + "` | " + docs_default(r) + " | " + flag + " | " + r.spec.doc + values + " |\n";
  }
  t += "| `progress`, `cancel` | none | – | a callback `(stage, fraction)` between steps; an `std::atomic<bool>*` that "
       "stops the conversion with `ahd::Cancelled` |\n";
  return t;
}

}  // namespace ahd
