// The conversion options, declared once: one row per member of ahd::ConversionOptions (<ahd/convert.h>)
// with its C member (ahd_options, <ahd/ahd.h>), command-line flag and help, enumeration values
// (core/option_enums.h), whether it is in the conversion key, and its docs line. What iterates the
// rows:
//   - ahd_options_init and the C → C++ conversion (api/c_api.cpp);
//   - the CLI's flags of convert and transcode (cli/conversion_args.cpp);
//   - the cache key's option lines (cook/conversion_key.cpp);
//   - the options table of docs/library.md (test OptionTable.DocsTableMatchesTheTable prints it);
//   - the tests: every keyed option changes the key, every C member reaches its C++ member.
// Defaults are the public struct's member initialisers, nowhere else: the rows read them from a
// default-constructed ConversionOptions. docs/maintaining.md "Adding a conversion option".
#pragma once
#include <ahd/ahd.h>
#include <ahd/convert.h>

#include <cstddef>
#include <functional>
#include <string>
#include <variant>
#include <vector>

namespace ahd {

// How an option enters the conversion key (cook/conversion_key.h).
enum class KeyForm {
  None,   // not in the key: it never changes the output bytes (threads)
  Value,  // "name value": numbers as %.17g, booleans 0/1, enumerations by index, text as given
  Name,   // enumerations by name (the unset value of an optional one by its `unset` word)
  Hash,   // text by its SHA-256 (a whole profile definition)
  // "name value" as Value, only when the value is not the default: an option added after keys were
  // in use leaves the keys of the conversions that do not set it as they were.
  ValueIfSet,
};

// One value of an enumerated option: the CLI's / key's name and the C++ enumerator.
struct OptionEnumValue {
  const char* name;
  const char* cpp;
};

// What the row builders take besides the two members (C++20 designated initialisers in the table).
struct OptionSpec {
  const char* flag = nullptr;  // the CLI flag, nullptr for none (the CLI sets the option otherwise)
  const char* help = "";       // the flag's help
  bool negated = false;        // a boolean flag that sets the option false (--open-loop: closed_loop = false)
  bool fit_only = false;       // only on commands that fit (convert; transcode reuses a stored fit)
  bool non_negative = false;   // numbers: the CLI refuses negatives
  const char* cli_default = nullptr;  // enumerations: the CLI's own default, when it differs (and why, in help)
  KeyForm key = KeyForm::Value;
  const char* doc = "";        // the meaning column of the docs table (docs/library.md)
  const char* doc_default = nullptr;  // docs "default" column, when the value alone does not say it ("0 (all)")
};

enum class OptionType { Text, Bool, Int, Double, Enum };

struct OptionRow {
  const char* name;  // the member's name in ConversionOptions and in ahd_options; the key's field
  OptionType type;
  OptionSpec spec;
  std::vector<OptionEnumValue> values;  // Enum: in value order (the C integer is the index)
  const char* unset = nullptr;          // an optional enumeration: what no value means ("profile": the profile's)
  // A plain member, for the CLI to bind its flag to (Text, Bool, Int, Double); monostate for enumerations.
  std::variant<std::monostate, std::string ConversionOptions::*, bool ConversionOptions::*, int ConversionOptions::*,
               double ConversionOptions::*>
      member;
  size_t c_offset = 0, c_size = 0;  // the C member's place in ahd_options (the struct_size check)

  // The value as text: numbers %.17g, booleans 0/1, enumerations by name ("" when unset).
  std::function<std::string(const ConversionOptions&)> text;
  // The key's value text (by `spec.key`; empty for KeyForm::None).
  std::function<std::string(const ConversionOptions&)> key_text;
  // Sets the member from text (a CLI value); throws ahd::Error naming the flag and its choices.
  std::function<void(ConversionOptions&, const std::string&)> parse;
  // The C member → the C++ member; throws ahd::Error("invalid option NAME = V") out of range.
  std::function<void(const ahd_options&, ConversionOptions&)> from_c;
  // The C member ← the C++ default (ahd_options_init). Text points into static storage.
  std::function<void(ahd_options&)> c_default;
  // Moves the member away from its current value (tests: every keyed option changes the key).
  std::function<void(ConversionOptions&)> change;
};

// Whether row `r` writes a line in the key of options `o` (KeyForm).
bool option_in_key(const OptionRow& r, const ConversionOptions& o);

// Every conversion option, in key order; new rows go at the end (as new ahd_options members do).
const std::vector<OptionRow>& option_table();

// The row named `name`; throws ahd::Error for an unknown name.
const OptionRow& option_row(const std::string& name);

// The options table of docs/library.md (the markdown rows between its markers), from the table.
std::string options_docs_table();

}  // namespace ahd
