// The render settings by name, as front ends (the Python module) give and read them: each
// setting's name, type, documentation and choices, and the checks its values go through. A front
// end translates its values to and from SettingValue; the names, the choices and the messages live
// here, beside Settings.
#pragma once

#include "ppm/settings.h"

#include <cstdint>
#include <functional>
#include <string>
#include <variant>
#include <vector>

namespace ppm {

// A setting's value: the field's own type, or a choice by name (SettingType's order).
using SettingValue = std::variant<bool, int, uint32_t, uint64_t, double, std::string>;
enum class SettingType : uint8_t { Bool, Int, UInt32, UInt64, Double, Choice };

struct SettingInfo {
  std::string name;
  SettingType type;
  const char* doc;
  std::function<SettingValue(const Settings&)> get;
  // Throws std::invalid_argument naming the setting for a value of another type or an unknown choice.
  std::function<void(Settings&, const SettingValue&)> set;
};

// Every setting, in the byte order of their names.
const std::vector<SettingInfo>& settings_table();
// The setting called `name`, or nullptr.
const SettingInfo* find_setting(const std::string& name);
// The setting called `name`; std::invalid_argument listing the known names if there is none.
const SettingInfo& setting_named(const std::string& name);
// std::invalid_argument: "settings: <name> has the wrong type".
[[noreturn]] void wrong_setting_type(const std::string& name);
// Settings::validate(), and the ranges values from outside must also keep: radii whose square
// stays finite.
void check_settings(const Settings& s);

}  // namespace ppm
