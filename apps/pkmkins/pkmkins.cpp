// pkmkins: a LinuxCNC (uspace) kinematics module that answers with a pkmkit machine file's
// kinematics. The RTAPI/HAL glue only: what it computes lives in pkm::linuxcnc::KinsAdapter
// (src/pkm/linuxcnc/kins_adapter.hpp), unit-tested without LinuxCNC.
//
//   loadrt pkmkins machine=FILE.toml [units=mm|inch]
//
// machine: the machine file, relative to the INI file's directory unless absolute.
// units:   LinuxCNC's world length unit ([TRAJ] LINEAR_UNITS); default: the machine file's.
// The file is read once, here in rtapi_app_main; a file that does not load stops LinuxCNC at
// start with the file's own file:line:key error. The servo thread neither reads nor allocates.
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <exception>
#include <filesystem>

#include "emcpos.h"  // C++ parts of posemath first: kinematics.h is C without extern "C"
#include "hal.h"
#include "pkm/linuxcnc/kins_adapter.hpp"
#include "rtapi.h"
#include "rtapi_app.h"
extern "C" {
#include "kinematics.h"
}

MODULE_AUTHOR("The pkmkit developers");
MODULE_DESCRIPTION("Kinematics of a pkmkit machine file");
MODULE_LICENSE("MIT");

static char* machine = nullptr;
RTAPI_MP_STRING(machine, "pkmkit machine file (relative to the INI file's directory)");
static char* units = nullptr;
RTAPI_MP_STRING(units, "LinuxCNC's length unit, mm or inch (default: the machine file's)");

namespace {

using pkm::linuxcnc::KinsAdapter;
using pkm::linuxcnc::WorldPose;

// The HAL pins (memory from hal_malloc, as HAL requires).
struct Pins {
  hal_s32_t* fk_status;
  hal_s32_t* fk_iterations;
  hal_u32_t* fk_failures;
  hal_s32_t* ik_status;
  hal_u32_t* ik_failures;
  hal_s32_t* ik_failed_joint;
};

int component = -1;
Pins* pins = nullptr;
KinsAdapter* adapter = nullptr;

WorldPose world_of(const EmcPose& pose) {
  return {pose.tran.x, pose.tran.y, pose.tran.z, pose.a, pose.b, pose.c, pose.u, pose.v, pose.w};
}

void store(const WorldPose& world, EmcPose& pose) {
  pose.tran.x = world.x;
  pose.tran.y = world.y;
  pose.tran.z = world.z;
  pose.a = world.a;
  pose.b = world.b;
  pose.c = world.c;
}

void publish() {
  const pkm::linuxcnc::KinsCounters& counters = adapter->counters();
  *pins->fk_status = counters.fk_status;
  *pins->fk_iterations = counters.fk_iterations;
  *pins->fk_failures = counters.fk_failures;
  *pins->ik_status = counters.ik_status;
  *pins->ik_failures = counters.ik_failures;
  *pins->ik_failed_joint = counters.ik_failed_joint;
}

int make_pins() {
  pins = static_cast<Pins*>(hal_malloc(sizeof(Pins)));
  if (pins == nullptr) return -ENOMEM;
  const int results[] = {
      hal_pin_s32_newf(HAL_OUT, &pins->fk_status, component, "pkmkins.fk-status"),
      hal_pin_s32_newf(HAL_OUT, &pins->fk_iterations, component, "pkmkins.fk-iterations"),
      hal_pin_u32_newf(HAL_OUT, &pins->fk_failures, component, "pkmkins.fk-failures"),
      hal_pin_s32_newf(HAL_OUT, &pins->ik_status, component, "pkmkins.ik-status"),
      hal_pin_u32_newf(HAL_OUT, &pins->ik_failures, component, "pkmkins.ik-failures"),
      hal_pin_s32_newf(HAL_OUT, &pins->ik_failed_joint, component, "pkmkins.ik-failed-joint"),
  };
  for (const int result : results) {
    if (result != 0) return result;
  }
  return 0;
}

// Whether LinuxCNC's INI file (INI_FILE_NAME) agrees with the machine file on the number of
// joints and the length unit; prints why not.
bool agrees_with_ini() {
  const char* ini_file = std::getenv("INI_FILE_NAME");
  if (ini_file == nullptr || *ini_file == '\0') return true;
  std::string mismatch;
  try {
    mismatch = pkm::linuxcnc::ini_mismatch(*adapter, pkm::linuxcnc::IniFile::read(ini_file));
  } catch (const pkm::linuxcnc::ConfigError&) {
    return true;  // LinuxCNC itself reads the INI and reports what is wrong with it
  }
  if (mismatch.empty()) return true;
  rtapi_print_msg(RTAPI_MSG_ERR, "pkmkins: %s\n", mismatch.c_str());
  return false;
}

// Reads the machine file named by the module parameters; prints why not and returns false.
bool load_machine_file() {
  if (machine == nullptr || *machine == '\0') {
    rtapi_print_msg(RTAPI_MSG_ERR,
                    "pkmkins: no machine file: load the module as `loadrt pkmkins "
                    "machine=FILE.toml` ([KINS] KINEMATICS = pkmkins machine=FILE.toml)\n");
    return false;
  }
  std::optional<pkm::machine::LengthUnit> world_unit;
  if (units != nullptr && *units != '\0') {
    world_unit = pkm::linuxcnc::parse_world_unit(units);
    if (!world_unit) {
      rtapi_print_msg(RTAPI_MSG_ERR, "pkmkins: units=%s: must be mm or inch\n", units);
      return false;
    }
  }
  try {
    char cwd[PATH_MAX];
    const std::filesystem::path file = pkm::linuxcnc::resolve_machine_file(
        machine, std::getenv("INI_FILE_NAME"), getcwd(cwd, sizeof cwd) ? cwd : ".");
    adapter = new KinsAdapter(pkm::linuxcnc::load_kins(file, world_unit));
    if (!agrees_with_ini()) {
      delete adapter;
      adapter = nullptr;
      return false;
    }
    rtapi_print_msg(RTAPI_MSG_INFO, "pkmkins: %s: '%s', %d joints, world unit %s\n", file.c_str(),
                    adapter->machine().name().c_str(), adapter->joint_count(),
                    adapter->world_unit() == pkm::machine::LengthUnit::inch ? "inch" : "mm");
    return true;
  } catch (const std::exception& error) {
    rtapi_print_msg(RTAPI_MSG_ERR, "pkmkins: %s\n", error.what());
    return false;
  }
}

}  // namespace

extern "C" {

int kinematicsForward(const double* joints, EmcPose* pose, const KINEMATICS_FORWARD_FLAGS*,
                      KINEMATICS_INVERSE_FLAGS*) {
  WorldPose world = world_of(*pose);
  const pkm::kinematics::Status status = adapter->forward(joints, world);
  publish();
  if (!status.ok()) return -1;
  store(world, *pose);
  return 0;
}

int kinematicsInverse(const EmcPose* pose, double* joints, const KINEMATICS_INVERSE_FLAGS*,
                      KINEMATICS_FORWARD_FLAGS*) {
  const pkm::kinematics::Status status = adapter->inverse(world_of(*pose), joints);
  publish();
  if (status.ok()) return 0;
  // LinuxCNC 2.9's motion stops on a non-zero return ("kinematicsInverse failed", the machine
  // is disabled); this says which joint and why. Its error messages reach the GUI too.
  if (adapter->should_report_failure()) {
    char message[512];
    rtapi_print_msg(RTAPI_MSG_ERR, "%s\n", adapter->failure_message(message, sizeof message));
  }
  return -1;
}

int kinematicsHome(EmcPose* pose, double* joints, KINEMATICS_FORWARD_FLAGS* forward_flags,
                   KINEMATICS_INVERSE_FLAGS* inverse_flags) {
  WorldPose world = world_of(*pose);
  adapter->home(world, joints);
  store(world, *pose);
  *forward_flags = 0;
  *inverse_flags = 0;
  return 0;
}

KINEMATICS_TYPE kinematicsType(void) {
  return KINEMATICS_BOTH;
}

// LinuxCNC 2.9's motion links against the switchable-kinematics entry points: pkmkins has one
// kinematics, so it is not switchable.
int kinematicsSwitchable(void) {
  return 0;
}

int kinematicsSwitch(int) {
  return 0;
}

int rtapi_app_main(void) {
  component = hal_init("pkmkins");
  if (component < 0) return component;
  if (!load_machine_file()) {
    hal_exit(component);
    return -EINVAL;
  }
  const int result = make_pins();
  if (result != 0) {
    rtapi_print_msg(RTAPI_MSG_ERR, "pkmkins: cannot create its HAL pins (%d)\n", result);
    hal_exit(component);
    delete adapter;
    adapter = nullptr;
    return result;
  }
  publish();
  hal_ready(component);
  return 0;
}

void rtapi_app_exit(void) {
  hal_exit(component);
  delete adapter;
  adapter = nullptr;
}

}  // extern "C"

EXPORT_SYMBOL(kinematicsType);
EXPORT_SYMBOL(kinematicsForward);
EXPORT_SYMBOL(kinematicsInverse);
EXPORT_SYMBOL(kinematicsHome);
EXPORT_SYMBOL(kinematicsSwitchable);
EXPORT_SYMBOL(kinematicsSwitch);
