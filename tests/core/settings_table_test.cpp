// The settings table (ppm/settings_table.h): names in order, values read and written as their
// fields' types, choices by name, and the messages front ends pass on; base/utf8.h's check.
#include "ppm/settings_table.h"

#include "base/utf8.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace ppm {
namespace {

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(SettingsTable, NamesAreInByteOrderAndFound) {
  const auto& table = settings_table();
  ASSERT_GT(table.size(), 30u);
  for (size_t i = 1; i < table.size(); ++i) EXPECT_LT(table[i - 1].name, table[i].name);
  for (const SettingInfo& s : table) EXPECT_EQ(find_setting(s.name), &s);
  EXPECT_EQ(find_setting("photon_count"), nullptr);
  EXPECT_EQ(message_of([] { setting_named("photon_count"); }).rfind("settings: unknown setting 'photon_count' (known: "
                                                                     "adaptive_samples, alpha, ",
                                                                     0),
            0u);
}

TEST(SettingsTable, EveryValueWrittenIsReadBack) {
  Settings s;
  for (const SettingInfo& setting : settings_table()) {
    const SettingValue value = setting.get(s);
    EXPECT_EQ(value.index(), static_cast<size_t>(setting.type)) << setting.name;
    setting.set(s, value);
    EXPECT_EQ(setting.get(s), value) << setting.name;
  }
  setting_named("alpha").set(s, 0.5);
  EXPECT_EQ(s.alpha, 0.5);
  setting_named("threshold").set(s, SettingValue(std::in_place_type<uint32_t>, 7u));
  EXPECT_EQ(s.threshold, 7u);
  setting_named("grid").set(s, std::string("hash"));
  EXPECT_EQ(s.grid, GridKind::Hash);
  EXPECT_EQ(std::get<std::string>(setting_named("grid").get(s)), "hash");
}

TEST(SettingsTable, RefusesOtherTypesAndUnknownChoices) {
  Settings s;
  EXPECT_EQ(message_of([&] { setting_named("alpha").set(s, std::string("high")); }),
            "settings: alpha has the wrong type");
  EXPECT_EQ(message_of([&] { setting_named("threshold").set(s, 3); }), "settings: threshold has the wrong type");
  EXPECT_EQ(message_of([&] { setting_named("grid").set(s, std::string("octree")); }),
            "settings: grid must be one of 'quantile', 'hash', not 'octree'");
  EXPECT_EQ(message_of([&] { setting_named("grid").set(s, std::string("\xff\xfe")); }),
            "settings: grid must be one of 'quantile', 'hash', not '\\xff\\xfe'");
}

TEST(SettingsTable, ChecksWhatValidateChecksAndTheRadii) {
  Settings s;
  s.alpha = 1.5;
  EXPECT_EQ(message_of([&] { check_settings(s); }), "settings: alpha must be in (0, 1)");
  s = Settings{};
  s.initial_radius = 1e31;
  EXPECT_EQ(message_of([&] { check_settings(s); }), "settings: initial_radius must be at most 1e30 m");
  s = Settings{};
  s.initial_radius_pixels = 2e6;
  EXPECT_EQ(message_of([&] { check_settings(s); }), "settings: initial_radius_pixels must be at most 1e6");
}

TEST(Utf8, AcceptsWellFormedTextOnly) {
  for (const char* good : {"", "abc", "\xc3\xa9", "\xe2\x82\xac", "\xef\xbf\xbf", "\xf0\x9f\x98\x80", "\xf4\x8f\xbf\xbf"})
    EXPECT_TRUE(valid_utf8(good)) << good;
  // A lone continuation, overlong forms, a surrogate, above U+10FFFF, cut short, bytes never used.
  for (const char* bad : {"\x80", "\xc0\xaf", "\xc1\xbf", "\xe0\x9f\xbf", "\xed\xa0\x80", "\xf0\x8f\xbf\xbf",
                          "\xf4\x90\x80\x80", "\xe2\x82", "\xf5\x80\x80\x80", "\xff"})
    EXPECT_FALSE(valid_utf8(bad)) << printable(bad);
  EXPECT_EQ(printable("a\xff" "b\xc3\xa9"), "a\\xffb\\xc3\\xa9");
  EXPECT_EQ(printable("\xc3\xa9"), "\xc3\xa9");
}

}  // namespace
}  // namespace ppm
