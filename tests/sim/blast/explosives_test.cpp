// Tests of sim/blast/explosives.
#include "sim/blast/explosives.hpp"

#include <set>
#include <string>

#include <gtest/gtest.h>

namespace brisance::blast {
namespace {

TEST(Explosives, ThesisTable2_1IsComplete) {
  const std::pair<const char*, double> thesis[] = {
      {"Amatol 80/20", 0.586}, {"Composition B", 1.148},     {"RDX", 1.185},
      {"HMX", 1.256},          {"Mercury fulminate", 0.395}, {"Nitroglycerin", 1.481},
      {"PETN", 1.282},         {"Pentolite 50/50", 1.129},   {"TNT", 1.000},
      {"Torpex", 1.667}};
  for (const auto& [name, factor] : thesis) {
    const auto explosive = find_explosive(name);
    ASSERT_TRUE(explosive.has_value()) << name;
    EXPECT_DOUBLE_EQ(explosive->tnt_factor, factor) << name;
    EXPECT_EQ(explosive->basis, "energy") << name;
  }
}

TEST(Explosives, EveryEntryHasAFactorABasisAndASource) {
  std::set<std::string> names;
  for (const Explosive& explosive : known_explosives()) {
    EXPECT_GT(explosive.tnt_factor, 0.3) << explosive.name;
    EXPECT_LT(explosive.tnt_factor, 2.0) << explosive.name;
    EXPECT_TRUE(explosive.basis == "energy" || explosive.basis == "pressure") << explosive.name;
    EXPECT_FALSE(explosive.source.empty()) << explosive.name;
    EXPECT_TRUE(names.insert(std::string(explosive.name)).second) << "duplicate " << explosive.name;
    // Every canonical name finds itself.
    ASSERT_TRUE(find_explosive(explosive.name).has_value()) << explosive.name;
    EXPECT_EQ(find_explosive(explosive.name)->name, explosive.name);
  }
  EXPECT_EQ(known_explosives().front().name, "TNT");
}

TEST(Explosives, LookupIgnoresCaseAndPunctuationAndKnowsAliases) {
  EXPECT_EQ(find_explosive("tnt")->name, "TNT");
  EXPECT_EQ(find_explosive("comp-b")->name, "Composition B");
  EXPECT_EQ(find_explosive("C4")->name, "Composition C-4");
  EXPECT_EQ(find_explosive("c-4")->name, "Composition C-4");
  EXPECT_EQ(find_explosive("pentolite")->name, "Pentolite 50/50");
  EXPECT_EQ(find_explosive("  anfo ")->name, "ANFO");
  EXPECT_FALSE(find_explosive("dynamite-x").has_value());
  EXPECT_FALSE(find_explosive("").has_value());
  EXPECT_FALSE(find_explosive("-").has_value());
}

TEST(Explosives, NamesListForErrorMessages) {
  const std::string names = known_explosive_names();
  for (const Explosive& explosive : known_explosives())
    EXPECT_NE(names.find(explosive.name), std::string::npos) << explosive.name;
  EXPECT_EQ(names.rfind("TNT, ", 0), 0u);
}

}  // namespace
}  // namespace brisance::blast
