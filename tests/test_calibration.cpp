// Calibration: the matrixkins formulas by hand, machine files written back, and least-squares
// fits that recover a known geometry from noisy synthetic measurements.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>

#include "pkm/calibration/fit_report.hpp"
#include "pkm/calibration/geometry_fit.hpp"
#include "pkm/calibration/identifiability.hpp"
#include "pkm/calibration/matrix_calibration.hpp"
#include "pkm/calibration/parameter_plausibility.hpp"
#include "pkm/kinematics/matrix.hpp"
#include "pkm/kinematics/rotary_delta.hpp"
#include "pkm/machine/machine_writer.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

TEST(MatrixCalibration, EachFormulaByHand) {
  calibration::MatrixMeasurements m;
  m.diagonals = {{141.5, 141.2}};
  m.widths = {{100.02, 100.0}};
  m.x_to_spindle = {{0.02, 200.0}};
  m.y_to_spindle = {{-0.03, 150.0}};
  m.z_tilt_x = {{0.01, 100.0}};
  m.z_tilt_y = {{-0.004, 80.0}};
  const Eigen::Matrix3d c = calibration::calibrate_matrix(m);
  EXPECT_DOUBLE_EQ(c(0, 1), (141.2 * 141.2 - 141.5 * 141.5) / (2 * 141.5 * 141.2));
  EXPECT_NEAR(c(0, 1), -0.0021223936, 1e-10);
  EXPECT_NEAR(c(1, 1), 1.0002, 1e-15);
  EXPECT_DOUBLE_EQ(c(2, 0), 0.0001);
  EXPECT_DOUBLE_EQ(c(2, 1), -0.0002);
  EXPECT_DOUBLE_EQ(c(0, 2), -0.0001);
  EXPECT_DOUBLE_EQ(c(1, 2), 0.00005);
  EXPECT_EQ(c(0, 0), 1.0);
  EXPECT_EQ(c(1, 0), 0.0);
  EXPECT_EQ(c(2, 2), 1.0);
}

TEST(MatrixCalibration, RecalibrationAddsToTheOldValues) {
  // The mill's file has C_xy = 0.0003, C_xz = -0.0001: new adjustments add to them.
  const machine::Machine mill = test::load_example("matrix-mill.toml");
  const auto& start =
      dynamic_cast<const kinematics::MatrixKinematics&>(mill.kinematics()).coefficients();
  calibration::MatrixMeasurements m;
  m.diagonals = {{141.5, 141.2}};
  m.z_tilt_x = {{0.01, 100.0}};
  const Eigen::Matrix3d c = calibration::calibrate_matrix(m, start);
  EXPECT_DOUBLE_EQ(c(0, 1), 0.0003 + (141.2 * 141.2 - 141.5 * 141.5) / (2 * 141.5 * 141.2));
  EXPECT_DOUBLE_EQ(c(0, 2), -0.0001 - 0.0001);
  EXPECT_DOUBLE_EQ(c(2, 0), 0.0002);  // untouched
  // A scale re-calibration multiplies the scale already in effect.
  Eigen::Matrix3d scaled = Eigen::Matrix3d::Identity();
  scaled(1, 1) = 1.01;
  calibration::MatrixMeasurements widths;
  widths.widths = {{100.0, 101.0}};
  EXPECT_DOUBLE_EQ(calibration::calibrate_matrix(widths, scaled)(1, 1),
                   1.01 + 1.01 * (100.0 / 101.0 - 1.0));
}

TEST(MatrixCalibration, ImpossibleMeasurementsNameTheFlag) {
  calibration::MatrixMeasurements zero_travel;
  zero_travel.x_to_spindle = {{0.02, 0.0}};
  EXPECT_THROW(
      {
        try {
          calibration::calibrate_matrix(zero_travel);
        } catch (const std::invalid_argument& error) {
          EXPECT_NE(std::string(error.what()).find("--x-to-spindle"), std::string::npos);
          throw;
        }
      },
      std::invalid_argument);
  calibration::MatrixMeasurements negative;
  negative.diagonals = {{-1.0, 1.0}};
  EXPECT_THROW(calibration::calibrate_matrix(negative), std::invalid_argument);
  calibration::MatrixMeasurements nan;
  nan.widths = {{std::nan(""), 1.0}};
  EXPECT_THROW(calibration::calibrate_matrix(nan), std::invalid_argument);
}

TEST(MatrixCalibration, ACorrectionNoMachineNeedsIsRefusedWithItsNumbers) {
  // A denormal travel made an infinite coefficient, written with exit status 0 (issue 26).
  calibration::MatrixMeasurements denormal;
  denormal.x_to_spindle = {{0.02, 1e-310}};
  try {
    calibration::calibrate_matrix(denormal);
    FAIL() << "an infinite C_zx was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what())
                  .find("--x-to-spindle: a reading of 0.02 over a travel of 1e-310 gives a "
                        "correction of inf, more than the 0.1"),
              std::string::npos)
        << error.what();
  }
  // Diagonals in inches and mm: 5.57 against 141.5 is no squareness error.
  calibration::MatrixMeasurements mixed_units;
  mixed_units.diagonals = {{141.5, 5.57}};
  EXPECT_THROW(calibration::calibrate_matrix(mixed_units), std::invalid_argument);
  calibration::MatrixMeasurements tilt;
  tilt.z_tilt_y = {{30.0, 80.0}};  // 0.375: 20 deg
  EXPECT_THROW(calibration::calibrate_matrix(tilt), std::invalid_argument);
  calibration::MatrixMeasurements scale;
  scale.widths = {{254.0, 100.0}};  // one of them in inches
  EXPECT_THROW(calibration::calibrate_matrix(scale), std::invalid_argument);
  // The largest real ones pass: 5 deg of tilt, 40 % of scale.
  calibration::MatrixMeasurements largest;
  largest.z_tilt_x = {{8.7, 100.0}};
  largest.widths = {{140.0, 100.0}};
  EXPECT_NO_THROW(calibration::calibrate_matrix(largest));
}

TEST(MatrixCalibration, LinuxcncLines) {
  Eigen::Matrix3d c = Eigen::Matrix3d::Identity();
  c(0, 1) = -0.0021;
  const std::string lines = calibration::linuxcnc_setp_lines(c);
  EXPECT_NE(lines.find("setp matrixkins.C_xx 1\n"), std::string::npos);
  EXPECT_NE(lines.find("setp matrixkins.C_xy -0.0021\n"), std::string::npos);
  EXPECT_NE(lines.find("setp matrixkins.C_zz 1\n"), std::string::npos);
}

TEST(MachineWriter, EveryExampleRoundTripsThroughItsKinematicsSection) {
  for (const std::string& file : test::example_machine_files()) {
    const machine::Machine machine = test::load_example(file);
    std::ifstream in(test::example_machine_path(file));
    const std::string original((std::istreambuf_iterator<char>(in)), {});
    const std::string rewritten =
        machine::replace_kinematics_section(original, file, machine.kinematics(), machine.units());
    const machine::Machine reread = machine::parse_machine(rewritten, file);
    const auto before = machine.kinematics().parameters();
    const auto after = reread.kinematics().parameters();
    ASSERT_EQ(before.size(), after.size()) << file;
    for (std::size_t i = 0; i < before.size(); ++i) {
      EXPECT_EQ(before[i].name, after[i].name);
      EXPECT_DOUBLE_EQ(before[i].value, after[i].value) << file << " " << before[i].name;
    }
    EXPECT_EQ(reread.joint_names(), machine.joint_names()) << file;
    EXPECT_EQ(reread.name(), machine.name()) << file;
  }
}

// Measurements of a machine whose true geometry is the nominal one plus `delta`.
std::vector<calibration::Measurement> synthetic_measurements(const machine::Machine& nominal,
                                                             const std::vector<double>& truth,
                                                             int count, double noise_mm,
                                                             std::mt19937_64& rng,
                                                             bool measure_angles = true) {
  std::unique_ptr<kinematics::Kinematics> true_model = nominal.kinematics().clone();
  true_model->set_parameters(truth);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<calibration::Measurement> data;
  for (const geometry::Pose& pose :
       test::sample_reachable_poses(nominal, 4 * count, rng, 10.0, 0.05)) {
    if (static_cast<int>(data.size()) == count) break;
    calibration::Measurement m;
    if (!true_model->inverse(pose, m.joints).ok()) continue;
    // A pose the nominal machine cannot place (cables that do not meet, within the perturbation
    // of the anchor line) is not one a user measures.
    geometry::Pose placed = nominal.home();
    if (!nominal.kinematics().forward(m.joints, placed).ok()) continue;
    m.pose = pose.as_vector();
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      const bool controlled = nominal.kinematics().dof().controls(axis);
      m.measured[axis] = controlled && (axis < 3 || measure_angles);
      if (m.measured[axis]) m.pose[axis] += (axis < 3 ? noise_mm : noise_mm / 100.0) * noise(rng);
    }
    m.line = static_cast<int>(data.size()) + 2;
    data.push_back(m);
  }
  return data;
}

struct FitCase {
  std::string file;
  std::vector<std::string> parameters;  // patterns to fit
  double perturbation;                  // size of the true deviation of each fitted parameter
};

std::ostream& operator<<(std::ostream& out, const FitCase& c) {
  return out << c.file;
}

class RecoversKnownGeometry : public ::testing::TestWithParam<FitCase> {};

TEST_P(RecoversKnownGeometry, WithinThreeSigmaAndDownToTheNoise) {
  const FitCase& c = GetParam();
  machine::Machine machine = test::load_example(c.file);
  std::mt19937_64 rng(42);
  const std::vector<kinematics::Parameter> parameters = machine.kinematics().parameters();
  std::vector<double> truth;
  std::uniform_real_distribution<double> sign(-1.0, 1.0);
  calibration::FitOptions options;
  options.parameters = c.parameters;
  // Perturb exactly the parameters the case fits.
  machine::Machine probe = machine;
  const calibration::FitReport selection =
      calibration::fit_geometry(probe.kinematics(), probe.home(),
                                synthetic_measurements(
                                    machine,
                                    [&] {
                                      std::vector<double> v;
                                      for (const kinematics::Parameter& p : parameters)
                                        v.push_back(p.value);
                                      return v;
                                    }(),
                                    50, 0.0, rng),
                                options);
  std::vector<std::string> fitted_names;
  for (const calibration::ParameterEstimate& p : selection.parameters) {
    if (p.free) fitted_names.push_back(p.name);
  }
  for (const kinematics::Parameter& p : parameters) {
    const bool fitted =
        std::find(fitted_names.begin(), fitted_names.end(), p.name) != fitted_names.end();
    truth.push_back(p.value + (fitted ? c.perturbation * sign(rng) : 0.0));
  }
  const double noise_mm = 0.005;
  const std::vector<calibration::Measurement> data =
      synthetic_measurements(machine, truth, 150, noise_mm, rng);
  const calibration::FitReport report =
      calibration::fit_geometry(machine.kinematics(), machine.home(), data, options);

  EXPECT_TRUE(report.converged);
  EXPECT_TRUE(report.held.empty()) << "first held: " << report.held.front();
  int measured_per_row = 0;
  for (const bool measured : data.front().measured) measured_per_row += measured ? 1 : 0;
  const double noise_level = noise_mm * std::sqrt(static_cast<double>(measured_per_row));
  EXPECT_GT(report.rms_before_mm, 10 * noise_level) << "the perturbation must be visible";
  EXPECT_LT(report.rms_after_mm, 1.3 * noise_level);
  EXPECT_GT(report.rms_after_mm, 0.6 * noise_level);
  for (const calibration::ParameterEstimate& p : report.parameters) {
    const std::size_t index = static_cast<std::size_t>(
        std::find_if(parameters.begin(), parameters.end(),
                     [&](const kinematics::Parameter& q) { return q.name == p.name; }) -
        parameters.begin());
    EXPECT_GT(p.standard_deviation, 0.0) << p.name;
    EXPECT_LE(std::abs(p.fitted - truth[index]), 3.0 * p.standard_deviation + 1e-12)
        << p.name << " fitted " << p.fitted << " true " << truth[index] << " sd "
        << p.standard_deviation;
  }
}

const FitCase kFitCases[] = {
    // The paper's ideal cables: what measured pen positions show of them.
    {"hektor.toml", {"anchor_*", "cable_offset_*"}, 0.5},
    {"wall-plotter.toml", {"anchor_*", "cable_offset_*"}, 2.0},
    {"matrix-mill.toml", {}, 1e-3},
    {"triaglide.toml", {"rail*.strut", "rail*.origin.*"}, 0.5},
    {"triaglide-fanned.toml", {"rail*.strut", "rail*.origin.*"}, 0.5},
    {"linear-delta.toml", {"rail*.strut", "rail*.origin.*"}, 0.5},
    {"hexaglide.toml", {"rail*.strut", "rail*.origin.z"}, 0.5},
    {"hexapod-bit.toml", {"leg*.offset", "leg*.base.*"}, 0.5},
    {"mach3-formula.toml", {"d"}, 3.0},
    {"linuxcnc-rdelta.toml", {"base_radius", "arm_length", "forearm_length"}, 0.5},
};

INSTANTIATE_TEST_SUITE_P(Examples, RecoversKnownGeometry, ::testing::ValuesIn(kFitCases),
                         [](const auto& test_info) {
                           return test::test_name(test_info.param.file);
                         });

// Two parameters whose residual columns are (1, 0, 0) and (1, 1, 0), noise 1: J^T J = [[1, 1],
// [1, 2]], its inverse [[2, -1], [-1, 1]]: standard deviations sqrt 2 and 1, correlation
// -1/sqrt 2; alone, 1 and 1/sqrt 2. With plausible deviations 1 and 2 the first is held (sqrt 2
// > 1), and the second, then alone (1/sqrt 2 < 2), is kept.
TEST(Identifiability, PrecisionAndHoldsByHand) {
  Eigen::MatrixXd jacobian(3, 2);
  jacobian << 1, 1, 0, 1, 0, 0;
  const std::vector<calibration::ScreenedParameter> parameters = {
      {"a", "mm", "a thing", 0, 0, 1.0, "1"}, {"b", "mm", "a thing", 0, 0, 2.0, "2"}};
  const calibration::Precision precision = calibration::fit_precision(jacobian, parameters, 1.0);
  EXPECT_NEAR(precision.deviation[0], std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(precision.deviation[1], 1.0, 1e-12);
  EXPECT_NEAR(precision.correlation(0, 1), -1.0 / std::sqrt(2.0), 1e-12);
  ASSERT_EQ(precision.trades[0].size(), 1u);
  EXPECT_EQ(precision.trades[0][0].name, "b");
  const std::vector<calibration::PoorlyDetermined> held =
      calibration::poorly_determined(jacobian, parameters, 1.0);
  ASSERT_EQ(held.size(), 1u);
  EXPECT_EQ(held[0].name, "a");
  EXPECT_NEAR(held[0].standard_deviation, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(held[0].alone_deviation, 1.0, 1e-12);
  EXPECT_EQ(calibration::describe_trades(held[0].trades_with), "b (correlation -0.71)");
  // Ten times less noise pins both.
  EXPECT_TRUE(calibration::poorly_determined(jacobian, parameters, 0.1).empty());
}

// Each model says what its parameters stand for; the kinds and deviations are docs/calibration.md's
// table, the texts those of the fit's messages.
TEST(Identifiability, PlausibleDeviationsByKind) {
  const auto judged = [](const std::string& file, const std::string& name, double value) {
    std::vector<kinematics::Parameter> parameters =
        test::load_example(file).kinematics().parameters();
    const auto found = std::find_if(parameters.begin(), parameters.end(),
                                    [&](const kinematics::Parameter& p) { return p.name == name; });
    if (found == parameters.end()) throw std::runtime_error(file + " has no " + name);
    found->value = value;
    return calibration::parameter_plausibility(*found, 1500.0);
  };
  const auto deviation = [&](const std::string& file, const std::string& name, double value) {
    return judged(file, name, value).deviation;
  };
  EXPECT_DOUBLE_EQ(deviation("hektor-pulleys.toml", "pulley_radius", 6.366), 0.2 * 6.366);
  EXPECT_EQ(judged("hektor-pulleys.toml", "pulley_radius", 6.366).rule,
            "20 % of its nominal value");
  EXPECT_DOUBLE_EQ(deviation("hektor.toml", "anchor_right_x", 1500.0), 2.0 + 0.02 * 1500.0);
  EXPECT_EQ(judged("hektor.toml", "anchor_right_x", 1500.0).rule,
            "2 mm + 2 % of the machine's size of 1500 mm");
  EXPECT_EQ(judged("hektor.toml", "cable_offset_left", 0.0).kind, "a cable's zero");
  EXPECT_DOUBLE_EQ(deviation("hektor.toml", "effector_mass", 0.3), 0.15);
  EXPECT_EQ(deviation("hektor.toml", "effector_mass", 0.0), 0.0);  // no mass: not judged
  EXPECT_DOUBLE_EQ(deviation("triaglide.toml", "rail2.direction.x", -0.5), 0.02);
  EXPECT_EQ(judged("triaglide.toml", "rail2.direction.x", -0.5).rule, "0.02");
  EXPECT_EQ(judged("triaglide.toml", "rail1.strut", 300.0).kind, "a strut's length");
  EXPECT_DOUBLE_EQ(deviation("hexapod-bit.toml", "leg3.offset", 0.0), 32.0);
  EXPECT_EQ(judged("hexapod-bit.toml", "tool_length", 0.0).kind, "the tool's length");
  EXPECT_EQ(judged("linuxcnc-rdelta.toml", "forearm_length", 0.0).kind, "a link's length");
  EXPECT_DOUBLE_EQ(deviation("matrix-mill.toml", "C_xy", 0.0), 0.01);
  EXPECT_EQ(judged("matrix-mill.toml", "C_xy", 0.0).kind, "a matrix coefficient");
  EXPECT_EQ(judged("mach3-formula.toml", "d", 3.0).deviation, 0.0);  // a constant: not judged
  EXPECT_EQ(judged("mach3-formula.toml", "d", 3.0).kind, "");
  // The machine's size: the larger of what was measured and the file's largest length.
  const std::vector<kinematics::Parameter> frame = {{"leg1.base.x", -320.0, "mm"},
                                                    {"C_xx", 1e4, ""}};
  EXPECT_EQ(calibration::machine_size_mm(frame, 100.0), 320.0);
  EXPECT_EQ(calibration::machine_size_mm(frame, 700.0), 700.0);
}

// Every pose fit's default parameters (all) on every example machine, measured at 20..40 poses
// spread over the reach to 0.05 mm: what the data cannot tell apart is held by rank, what they
// pin less well than the machine file by precision (with its numbers); no fit is refused, and
// every parameter fitted is pinned within its plausible deviation and lands within four
// standard deviations of the truth (the machine file's geometry: the held parameters are true).
TEST(GeometryFit, DefaultParametersOfEveryExampleArePinnedOrHeld) {
  for (const std::string& file : test::example_machine_files()) {
    machine::Machine machine = test::load_example(file);
    std::vector<double> truth;
    for (const kinematics::Parameter& p : machine.kinematics().parameters())
      truth.push_back(p.value);
    std::mt19937_64 rng(11);
    // A cable machine solves its forward kinematics by Newton's method (sag, a tilting effector):
    // 20 poses keep the test within seconds, 40 for the others.
    const int poses = machine.kinematics().type() == "cable_plotter" ? 20 : 40;
    const auto data = synthetic_measurements(machine, truth, poses, 0.05, rng);
    calibration::FitReport report;
    try {
      report = calibration::fit_geometry(machine.kinematics(), machine.home(), data, {});
    } catch (const calibration::FitError& error) {
      ADD_FAILURE() << file << ": " << error.what();
      continue;
    }
    int fitted = 0;
    for (std::size_t i = 0; i < truth.size(); ++i) {
      const calibration::ParameterEstimate& p = report.parameters[i];
      if (!p.free) continue;
      ++fitted;
      if (p.plausible_deviation > 0.0) {
        EXPECT_LE(p.standard_deviation, p.plausible_deviation) << file << " " << p.name;
      }
      EXPECT_LE(std::abs(p.fitted - truth[i]), 4.0 * p.standard_deviation + 1e-9)
          << file << " " << p.name << " fitted " << p.fitted << " true " << truth[i] << " sd "
          << p.standard_deviation;
    }
    EXPECT_GT(fitted, 0) << file;
    // Down to the noise: 0.05 mm on each of up to six coordinates (angles weighted alike).
    EXPECT_LT(report.rms_after_mm, 1.3 * 0.05 * std::sqrt(6.0)) << file;
  }
}

// A Hektor on GT2 pulleys measured with a camera over the wall (positions to 0.5 mm, 40 poses):
// its pulley radius trades with the cable offsets, and 0.5 mm cannot pin it within a fifth of
// itself. Held at its nominal 6.366 mm with the numbers, the rest fitted.
TEST(GeometryFit, APulleyTheCameraCannotPinIsHeldWithItsNumbers) {
  machine::Machine machine = test::load_example("hektor-pulleys.toml");
  std::vector<double> truth;
  for (const kinematics::Parameter& p : machine.kinematics().parameters())
    truth.push_back(p.value + (p.name == "cable_offset_left" ? 1.0 : 0.0));
  std::mt19937_64 rng(4);
  const auto data = synthetic_measurements(machine, truth, 40, 0.5, rng, false);
  const calibration::FitReport report =
      calibration::fit_geometry(machine.kinematics(), machine.home(), data, {});
  ASSERT_FALSE(report.poorly_determined.empty());
  const calibration::PoorlyDetermined& pulley = report.poorly_determined.front();
  std::printf("%s\n", calibration::poorly_determined_text(pulley).c_str());
  EXPECT_EQ(pulley.name, "pulley_radius");
  EXPECT_GT(pulley.standard_deviation, pulley.plausible_deviation);
  EXPECT_FALSE(pulley.trades_with.empty());
  for (const calibration::ParameterEstimate& p : report.parameters) {
    if (p.name == "pulley_radius") {
      EXPECT_FALSE(p.free);
      EXPECT_EQ(p.fitted, 6.366);
    }
  }
}

TEST(GeometryFit, ASledsMassMovesNothingAndIsHeld) {
  // A gondola without sag or stretch: its mass scales both tensions and moves no pen, so no
  // measured pose can tell it. Forward kinematics' differencing noise once fitted it to 1.83 kg
  // for a true 0.18 kg (a newcomer's wall plotter).
  machine::Machine machine = test::load_example("makelangelo.toml");
  std::vector<double> values;
  for (const kinematics::Parameter& p : machine.kinematics().parameters()) {
    values.push_back(p.name == "cable_density" || p.name == "cable_stretch" ? 0.0 : p.value);
  }
  machine.kinematics().set_parameters(values);
  std::vector<double> truth = values;
  truth[2] += 3.0;  // anchor_right_x
  truth[5] += 2.0;  // cable_offset_left
  std::mt19937_64 rng(5);
  const std::vector<calibration::Measurement> data =
      synthetic_measurements(machine, truth, 30, 0.0, rng, false);
  const calibration::FitReport report =
      calibration::fit_geometry(machine.kinematics(), machine.home(), data, {});
  EXPECT_NE(std::find(report.no_effect.begin(), report.no_effect.end(), "effector_mass"),
            report.no_effect.end());
  for (const calibration::ParameterEstimate& p : report.parameters) {
    if (p.name == "effector_mass") {
      EXPECT_EQ(p.fitted, p.nominal);
    }
  }
  EXPECT_LT(report.rms_after_mm, 1e-3);
}

TEST(GeometryFit, ReportsWhatTheDataCannotIdentify) {
  // Every measurement at z = 0: the z column of C never acts on the data.
  machine::Machine mill = test::load_example("matrix-mill.toml");
  std::vector<calibration::Measurement> data;
  for (int i = 0; i < 40; ++i) {
    calibration::Measurement m;
    const geometry::Pose pose =
        geometry::Pose::from_mm_deg(20.0 + 13.0 * i, 10.0 + 9.0 * (i % 7), 0.0);
    ASSERT_TRUE(mill.kinematics().inverse(pose, m.joints).ok());
    m.pose = pose.as_vector();
    m.measured = {true, true, true, false, false, false};
    m.line = i + 2;
    data.push_back(m);
  }
  const calibration::FitReport report =
      calibration::fit_geometry(mill.kinematics(), mill.home(), data, {});
  std::vector<std::string> held = report.held;
  std::sort(held.begin(), held.end());
  EXPECT_EQ(held, (std::vector<std::string>{"C_xz", "C_yz", "C_zz"}));
  // No effect at all: named as such, not as a group the data cannot tell apart.
  EXPECT_EQ(report.no_effect, (std::vector<std::string>{"C_xz", "C_yz", "C_zz"}));
  EXPECT_TRUE(report.indistinguishable.empty());
  for (const calibration::ParameterEstimate& p : report.parameters) {
    if (!p.free) {
      EXPECT_EQ(p.fitted, p.nominal) << p.name << " must stay at its nominal value";
    }
  }
  EXPECT_LT(report.rms_after_mm, 1e-9);
}

TEST(GeometryFit, HexapodWithEveryParameterHoldsTheUnidentifiableOnes) {
  // Positions only: the platform's own frame (its orientation, the tool length against the
  // platform joints' height) is not in the data. The fit must hold those and still fit.
  machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  std::mt19937_64 rng(8);
  std::vector<double> truth;
  std::normal_distribution<double> deviation(0.0, 0.3);
  for (const kinematics::Parameter& p : hexapod.kinematics().parameters())
    truth.push_back(p.value + deviation(rng));
  const auto data = synthetic_measurements(hexapod, truth, 200, 0.0, rng, false);
  const calibration::FitReport report =
      calibration::fit_geometry(hexapod.kinematics(), hexapod.home(), data, {});
  EXPECT_FALSE(report.held.empty());
  EXPECT_FALSE(report.indistinguishable.empty());
  EXPECT_GT(report.rms_before_mm, 0.1);
  EXPECT_LT(report.rms_after_mm, 1e-6);
}

TEST(GeometryFit, RotaryDeltaHoldsOneOfItsTwoRadii) {
  // A translating platform's tool point sees the pivots' radius and the platform joints' only as
  // their difference (each forearm runs from the elbow to the tool point moved out by the
  // platform radius): the two cannot be told apart, and the fit holds one at nominal.
  machine::Machine rdelta = test::load_example("linuxcnc-rdelta.toml");
  std::mt19937_64 rng(9);
  std::vector<double> truth;
  for (const kinematics::Parameter& p : rdelta.kinematics().parameters())
    truth.push_back(p.value + 0.4);
  const auto data = synthetic_measurements(rdelta, truth, 100, 0.0, rng);
  const calibration::FitReport report =
      calibration::fit_geometry(rdelta.kinematics(), rdelta.home(), data, {});
  ASSERT_EQ(report.held.size(), 1u);
  ASSERT_EQ(report.indistinguishable.size(), 1u);
  std::vector<std::string> group = report.indistinguishable.front();
  std::sort(group.begin(), group.end());
  EXPECT_EQ(group, (std::vector<std::string>{"base_radius", "platform_radius"}));
  EXPECT_GT(report.rms_before_mm, 0.1);
  EXPECT_LT(report.rms_after_mm, 1e-6);
  const auto& fitted =
      dynamic_cast<const kinematics::RotaryDeltaKinematics&>(rdelta.kinematics()).geometry();
  EXPECT_NEAR(fitted.base_radius_mm - fitted.platform_radius_mm, truth[0] - truth[3], 1e-6);
  EXPECT_NEAR(fitted.forearm_length_mm, truth[2], 1e-6);
}

TEST(GeometryFit, UnknownParameterNameIsAnError) {
  machine::Machine hektor = test::load_example("hektor.toml");
  std::mt19937_64 rng(1);
  std::vector<double> nominal;
  for (const kinematics::Parameter& p : hektor.kinematics().parameters())
    nominal.push_back(p.value);
  const auto data = synthetic_measurements(hektor, nominal, 10, 0.0, rng);
  calibration::FitOptions options;
  options.parameters = {"anchor_distanse"};
  EXPECT_THROW(calibration::fit_geometry(hektor.kinematics(), hektor.home(), data, options),
               calibration::FitError);
}

TEST(Measurements, CsvErrorsNameLineAndColumn) {
  const machine::Machine hektor = test::load_example("hektor.toml");
  const auto error_of = [&](const std::string& text) {
    try {
      calibration::parse_measurements_csv(text, "data.csv", hektor);
    } catch (const calibration::MeasurementFileError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error_of("j_left,j_right,x,y\n60,80,36,-48\n"), "accepted");
  EXPECT_EQ(error_of("j_left,j_right,x,y\n60,eighty,36,-48\n"),
            "data.csv:2:4: 'eighty' is not a number");
  EXPECT_EQ(error_of("j_left,j_rigth,x,y\n"),
            "data.csv:1:8: unknown column 'j_rigth' (expected j_<joint name>, x y z a b c, t or "
            "line)");
  EXPECT_EQ(error_of("j_left,j_right,x,z\n"),
            "data.csv:1:18: column 'z': this machine does not control z");
  EXPECT_EQ(error_of("j_left,x,y\n"), "data.csv:1:1: no column 'j_right'");
  EXPECT_EQ(error_of("j_left,j_right,x,y\n60,80,36\n"),
            "data.csv:2:1: has 3 fields; the header has 4");
  EXPECT_EQ(error_of("j_left,j_right,x,y\n60,80,nan,-48\n"), "data.csv:2:7: must be finite");
  EXPECT_EQ(error_of("j_left,j_right\n"), "data.csv:1:1: no measured pose column (x y z a b c)");
  const auto data = calibration::parse_measurements_csv(
      "t,line,j_left,j_right,x,y\n0,1,60,80,36,-48\n", "data.csv", hektor);
  ASSERT_EQ(data.size(), 1u);
  EXPECT_EQ(data[0].joints[1], 80.0);
  EXPECT_EQ(data[0].pose[1], -48.0);
  EXPECT_TRUE(data[0].measured[0]);
  EXPECT_FALSE(data[0].measured[2]);
}

}  // namespace
}  // namespace pkm
