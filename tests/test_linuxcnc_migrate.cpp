// pkm linuxcnc migrate on LinuxCNC's own sample configurations (skipped, with the reason, where
// they are not installed): the edits each needs, and nothing else changed. That the migrated
// configurations start and run in LinuxCNC is tests/linuxcnc's linuxcnc.migrated_* tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "pkm/linuxcnc/config_migrate.hpp"
#include "pkm/linuxcnc/ini_file.hpp"

namespace pkm::linuxcnc {
namespace {

namespace fs = std::filesystem;

const fs::path kSamples = fs::path(PKM_LINUXCNC_SAMPLES) / "sim/axis";

#define PKM_SKIP_WITHOUT_SAMPLE(path)                \
  do {                                               \
    if (!fs::exists(path))                           \
      GTEST_SKIP() << (path).string()                \
                   << " is not installed (Debian: "  \
                      "linuxcnc-uspace's examples)"; \
  } while (false)

MigrateOptions options(const std::string& name, int joints, const std::string& units) {
  MigrateOptions o;
  o.machine_file_name = name;
  o.machine_text = "# the machine file\n";
  o.machine_joints = joints;
  o.machine_units = units;
  return o;
}

const std::string& text_of(const Migration& migration, const std::string& name) {
  const auto file = std::find_if(migration.files.begin(), migration.files.end(),
                                 [&](const ConfigFile& f) { return f.name == name; });
  if (file == migration.files.end()) throw std::runtime_error(name + " is not in the migration");
  return file->text;
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// genhexkins with switchkins: KINEMATICS, the geometry's setp lines, genhexkins' and kinstype's
// pins in nets, and motion.switchkins-type in the INI's HALCMD.
TEST(LinuxcncMigrate, HexapodSimSwitchesGenhexkinsToPkmkins) {
  const fs::path ini = kSamples / "vismach/hexapod-sim/hexapod.ini";
  PKM_SKIP_WITHOUT_SAMPLE(ini);
  const Migration m = migrate_linuxcnc_config(ini, options("hexapod.toml", 6, "inch"));
  EXPECT_EQ(m.module, "genhexkins");
  const std::string& new_ini = text_of(m, "hexapod.ini");
  EXPECT_TRUE(has(new_ini,
                  "\nKINEMATICS = pkmkins machine=hexapod.toml\nPKM_MACHINE = "
                  "hexapod.toml\n"));
  EXPECT_FALSE(has(new_ini, "\nKINEMATICS = genhexkins"));
  EXPECT_TRUE(has(new_ini, "\nHALCMD = net :kinstype-select <= motion.analog-out-03\n"));
  EXPECT_FALSE(has(new_ini, "\nHALCMD  = net :kinstype-select <= motion.analog-out-03 =>"));
  // The remaps, panel and HALUI commands stay as they were.
  EXPECT_TRUE(has(new_ini, "REMAP = M428  modalgroup=10  ngc=428remap"));
  EXPECT_TRUE(has(new_ini, "PYVCP = hexapod.xml"));
  const std::string& kinematics = text_of(m, "kinematics.hal");
  EXPECT_TRUE(has(kinematics, "\n# pkm linuxcnc migrate: setp genhexkins.base.0.x -22.950\n"));
  EXPECT_TRUE(has(kinematics, "\nnet tool-offset motion.tooloffset.z\n"));
  const std::string& postgui = text_of(m, "hexapod_postgui.hal");
  EXPECT_TRUE(has(postgui, "\nnet :fwd-kins-fail => pyvcp.fwd-kins-fail\n"));
  EXPECT_TRUE(has(postgui, "net :kinstype.is-0 => pyvcp.multilabel.0.legend0\n"));
  EXPECT_TRUE(has(postgui, "net :j0 <= joint.0.pos-fb => pyvcp.joint0 => hexagui.joint.0"));
  EXPECT_EQ(text_of(m, "remap_subs/428remap.ngc"),
            read_config_text(kSamples / "vismach/hexapod-sim/remap_subs/428remap.ngc"));
  EXPECT_EQ(text_of(m, "hexapod.toml"), "# the machine file\n");
  EXPECT_EQ(m.warnings.size(), 3u);  // the three switchkins remaps
}

// lineardeltakins' geometry comes from a HAL file of LinuxCNC's library: copied and edited.
TEST(LinuxcncMigrate, LdeltaCopiesTheLibraryHalFileItEdits) {
  const fs::path ini = kSamples / "ldelta.ini";
  PKM_SKIP_WITHOUT_SAMPLE(ini);
  const Migration m = migrate_linuxcnc_config(ini, options("ldelta.toml", 4, "mm"));
  const std::string& hal = text_of(m, "sim_ldelta.hal");
  EXPECT_TRUE(has(hal, "\nnet L => lineardelta.L\n")) << hal;
  EXPECT_TRUE(has(hal, "\nsets L 269\n")) << hal;  // the vismach model's geometry, kept
  EXPECT_TRUE(has(hal, "\nloadrt [KINS]KINEMATICS\n"));
  EXPECT_TRUE(has(text_of(m, "ldelta.ini"), "\nKINEMATICS = pkmkins machine=ldelta.toml\n"));
  EXPECT_TRUE(
      has(text_of(m, "ldelta.ini"),
          "\nPROGRAM_PREFIX = " + (kSamples / "../../../nc_files/").lexically_normal().string()));
}

// LinuxCNC's unit differs from the machine file's: units= says it to pkmkins.
TEST(LinuxcncMigrate, AddsUnitsWhereTheMachineFileIsInOtherUnits) {
  const fs::path ini = kSamples / "vismach/hexapod-sim/hexapod.ini";
  PKM_SKIP_WITHOUT_SAMPLE(ini);
  const Migration m = migrate_linuxcnc_config(ini, options("hexapod.toml", 6, "mm"));
  EXPECT_TRUE(
      has(text_of(m, "hexapod.ini"), "\nKINEMATICS = pkmkins machine=hexapod.toml units=inch\n"));
}

TEST(LinuxcncMigrate, RefusesJointsTheMachineFileDoesNotHave) {
  const fs::path ini = kSamples / "rdelta.ini";
  PKM_SKIP_WITHOUT_SAMPLE(ini);
  try {
    (void)migrate_linuxcnc_config(ini, options("rdelta.toml", 3, "inch"));
    FAIL() << "migrated rdelta's 9 joints onto a 3-joint machine";
  } catch (const ConfigError& error) {
    EXPECT_TRUE(has(error.what(),
                    "rdelta.ini:60:[KINS]JOINTS: [KINS] JOINTS = 9 but rdelta.toml "
                    "has 3 joints"))
        << error.what();
  }
}

}  // namespace
}  // namespace pkm::linuxcnc
