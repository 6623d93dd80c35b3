// The strategy tables: every value of the public enumerations of <ahd/types.h> that a conversion
// option takes, with its name (the CLI's value, the key's and the intermediate's text) and its C++
// enumerator (the docs). One row per value, in value order: the C API's integer is the row's index,
// its range the table's size, the CLI's list of choices and the lab's loops over strategies iterate
// the rows. A new strategy (a third direction fit, a fifth BC6H effort) is one row here beside its
// enumerator; the option table (api/option_table.h) and every parser follow.
#pragma once
#include <ahd/types.h>

#include <array>
#include <cstddef>
#include <string_view>

namespace ahd {

template <typename E>
struct EnumName {
  E value;
  const char* name;  // lower case: the CLI's value, the key's and the intermediate's text
  const char* cpp;   // the C++ enumerator (docs)
};

inline constexpr std::array<EnumName<DirectionFit>, 2> kDirectionFits = {{
    {DirectionFit::Linear, "linear", "Linear"},
    {DirectionFit::Refined, "refined", "Refined"},
}};

inline constexpr std::array<EnumName<Bc6hQuality>, 4> kBc6hQualities = {{
    {Bc6hQuality::Fast, "fast", "Fast"},
    {Bc6hQuality::Default, "default", "Default"},
    {Bc6hQuality::High, "high", "High"},
    {Bc6hQuality::Max, "max", "Max"},
}};

inline constexpr std::array<EnumName<Measure>, 3> kMeasures = {{
    {Measure::Off, "off", "Off"},
    {Measure::Estimate, "estimate", "Estimate"},
    {Measure::Full, "full", "Full"},
}};

inline constexpr std::array<EnumName<DirectionPlanes>, 3> kDirectionPlanes = {{
    {DirectionPlanes::Auto, "auto", "Auto"},
    {DirectionPlanes::Keep, "keep", "Keep"},
    {DirectionPlanes::Drop, "drop", "Drop"},
}};

inline constexpr std::array<EnumName<RatioForm>, 2> kRatioForms = {{
    {RatioForm::Luminance, "luminance", "Luminance"},
    {RatioForm::Rgb, "rgb", "Rgb"},
}};

inline constexpr std::array<EnumName<ContainerKind>, 2> kContainerKinds = {{
    {ContainerKind::KTX2, "ktx2", "KTX2"},
    {ContainerKind::DDS, "dds", "DDS"},
}};

// True when every row's value is its index (the C API's integers are the indices).
template <typename E, std::size_t N>
constexpr bool values_are_indices(const std::array<EnumName<E>, N>& t) {
  for (std::size_t i = 0; i < N; ++i)
    if (static_cast<std::size_t>(t[i].value) != i) return false;
  return true;
}
static_assert(values_are_indices(kDirectionFits) && values_are_indices(kBc6hQualities) &&
              values_are_indices(kMeasures) && values_are_indices(kDirectionPlanes) &&
              values_are_indices(kRatioForms) && values_are_indices(kContainerKinds));

// The row's name of `v`; "?" for a value outside the table (a cast integer).
template <typename E, std::size_t N>
constexpr const char* enum_name(const std::array<EnumName<E>, N>& t, E v) {
  for (const EnumName<E>& r : t)
    if (r.value == v) return r.name;
  return "?";
}

// Sets *out to the value named `s`; false (and *out untouched) for a name not in the table.
template <typename E, std::size_t N>
constexpr bool parse_enum(const std::array<EnumName<E>, N>& t, std::string_view s, E* out) {
  for (const EnumName<E>& r : t)
    if (s == r.name) return *out = r.value, true;
  return false;
}

}  // namespace ahd
