// Python side of the render settings (ppm/settings_table.h): keyword arguments to Settings and
// back. The names, choices and checks are the table's; here Python values become SettingValues.
#include "ppm/settings_table.h"
#include "python/bindings.h"

#include <variant>

namespace py = pybind11;
using namespace ppm;

namespace {

// `value` as the setting's type, as pybind11 converts it ("has the wrong type" where it cannot).
SettingValue setting_value(const SettingInfo& setting, const py::handle& value) {
  try {
    switch (setting.type) {
      case SettingType::Bool: return value.cast<bool>();
      case SettingType::Int: return value.cast<int>();
      case SettingType::UInt32: return value.cast<uint32_t>();
      case SettingType::UInt64: return value.cast<uint64_t>();
      case SettingType::Double: return value.cast<double>();
      case SettingType::Choice: return value.cast<std::string>();
    }
  } catch (const py::cast_error&) {
  }
  wrong_setting_type(setting.name);
}

py::object python_value(const SettingValue& value) {
  return std::visit([](const auto& v) { return py::cast(v); }, value);
}

}  // namespace

namespace ppm::python {

Settings settings_from(const py::dict& values) {
  Settings s;
  for (const auto& [key, value] : values) {
    const SettingInfo& setting = setting_named(py::str(key));
    setting.set(s, setting_value(setting, value));
  }
  check_settings(s);
  return s;
}

py::dict settings_dict(const Settings& s) {
  py::dict d;
  for (const SettingInfo& setting : settings_table()) d[py::str(setting.name)] = python_value(setting.get(s));
  return d;
}

void bind_settings(py::module_& m) {
  py::class_<Settings>(m, "Settings", "Render settings; unknown names are an error.")
      .def(py::init([](const py::kwargs& kw) { return settings_from(kw); }))
      .def("as_dict", &settings_dict)
      .def("__repr__", [](const Settings& s) { return "Settings(" + py::str(settings_dict(s)).cast<std::string>() + ")"; })
      .def("__getattr__", [](const Settings& s, const std::string& name) {
        const SettingInfo* setting = find_setting(name);
        if (setting == nullptr) throw py::attribute_error("Settings has no setting '" + name + "'");
        return python_value(setting->get(s));
      });
  m.def("default_settings", []() { return settings_dict(Settings{}); }, "The default settings as a dict.");
}

}  // namespace ppm::python
