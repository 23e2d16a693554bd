// pkm workspace: hand-computed areas, the proof's claims checked at random poses, and a
// Monte-Carlo cross-check of every example machine's volume.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <set>
#include <sstream>

#include "pkm/kinematics/cable_tensions.hpp"
#include "pkm/kinematics/hexapod.hpp"
#include "pkm/workspace/pose_constraints.hpp"
#include "pkm/workspace/workspace.hpp"
#include "pkm/workspace/workspace_json.hpp"
#include "test_support.hpp"

namespace pkm::workspace {
namespace {

// Two carriages on one rail along x (readings 0..300 mm), struts of 100 mm to the platform point
// hanging below the rail: carriage 1 at x - f, carriage 2 at x + f, f = sqrt(100^2 - y^2).
machine::Machine biglide() {
  return machine::parse_machine(R"(
name = "biglide"
[kinematics]
type = "glide"
[[kinematics.rails]]
origin = [0.0, 0.0, 0.0]
direction = [1.0, 0.0, 0.0]
strut = 100.0
attach = [0.0, 0.0, 0.0]
branch = -1
[[kinematics.rails]]
origin = [0.0, 0.0, 0.0]
direction = [1.0, 0.0, 0.0]
strut = 100.0
attach = [0.0, 0.0, 0.0]
branch = 1
[[joints]]
name = "left"
min = 0.0
max = 300.0
max_velocity = 100.0
max_acceleration = 1000.0
[[joints]]
name = "right"
min = 0.0
max = 300.0
max_velocity = 100.0
max_acceleration = 1000.0
[cartesian]
max_feed = 6000.0
max_acceleration = 1000.0
home = [150.0, -50.0]
)",
                                "biglide.toml");
}

// Anchors 1000 mm apart, cables 10..1200 mm.
machine::Machine plotter() {
  return machine::parse_machine(R"(
name = "plotter"
[kinematics]
type = "cable_plotter"
anchor_distance = 1000.0
[[joints]]
name = "left"
min = 10.0
max = 1200.0
max_velocity = 100.0
max_acceleration = 1000.0
[[joints]]
name = "right"
min = 10.0
max = 1200.0
max_velocity = 100.0
max_acceleration = 1000.0
[cartesian]
max_feed = 6000.0
max_acceleration = 1000.0
home = [500.0, -500.0]
)",
                                "plotter.toml");
}

WorkspaceOptions at_resolution(const machine::Machine& machine, double resolution_mm) {
  WorkspaceOptions options = default_options(machine);
  options.resolution_mm = resolution_mm;
  return options;
}

TEST(Workspace, BiglideAreaFromItsRailAndStruts) {
  // For y in (-100, 0) the platform reaches x in [f, 300 - f]: the area is
  // 300 * 100 - 2 * (quarter disk of radius 100) = 30000 - 5000 pi = 14292.04 mm^2.
  const double exact = 30000.0 - 5000.0 * M_PI;
  const machine::Machine machine = biglide();
  const Workspace ws = compute_workspace(machine, at_resolution(machine, 0.5));
  EXPECT_TRUE(ws.planar);
  EXPECT_TRUE(ws.guaranteed);
  EXPECT_LE(ws.inside_measure, exact);
  EXPECT_GE(ws.inside_measure + ws.boundary_measure, exact);
  // Above the rail, where the struts stand nearly square to it, the assembly-mode bound cannot
  // decide: a strip of boundary cells stays there (docs/workspace.md).
  EXPECT_LT(ws.boundary_measure, 0.12 * exact);
  EXPECT_NEAR(ws.estimate, exact, 0.002 * exact);
  ASSERT_TRUE(ws.extent);
  EXPECT_NEAR(ws.extent->min().y(), -100.0, 1.0);
  // Both ends of the rail limit it, the struts' reach at y = -100 and the assembly mode at 0.
  EXPECT_GT(ws.limited_by.count("joint_limit"), 0u);
  EXPECT_GT(ws.limited_by.count("other_assembly"), 0u);
}

TEST(Workspace, CablePlotterBetweenTheAnchors) {
  // Between the anchors' verticals (x in (0, 1000)) and below them, each cable at most 1200 mm:
  // for x >= 500 the left cable is the longer, so the area is 2 * integral over [500, 1000] of
  // sqrt(1200^2 - x^2), less the quarter disks of radius 10 where a cable is below its min.
  const auto primitive = [](double x) {
    const double r = 1200.0;
    return 0.5 * (x * std::sqrt(r * r - x * x) + r * r * std::asin(x / r));
  };
  const double exact = 2.0 * (primitive(1000.0) - primitive(500.0)) - 0.5 * M_PI * 100.0;
  EXPECT_NEAR(exact, 917415.2, 0.5);
  const machine::Machine machine = plotter();
  const Workspace ws = compute_workspace(machine, at_resolution(machine, 2.0));
  EXPECT_TRUE(ws.guaranteed);
  EXPECT_LE(ws.inside_measure, exact);
  EXPECT_GE(ws.inside_measure + ws.boundary_measure, exact);
  EXPECT_NEAR(ws.estimate, exact, 0.002 * exact);
  ASSERT_TRUE(ws.extent);
  EXPECT_NEAR(ws.extent->min().x(), 0.0, 2.0);
  EXPECT_NEAR(ws.extent->max().x(), 1000.0, 2.0);
  EXPECT_NEAR(ws.extent->min().y(), -std::sqrt(1200.0 * 1200.0 - 500.0 * 500.0), 2.0);
  // The largest disk sits between the anchors, clear of both sides.
  ASSERT_TRUE(ws.largest_cylinder);
  EXPECT_GT(ws.largest_cylinder->radius_mm, 300.0);
  EXPECT_LT(ws.largest_cylinder->radius_mm, 500.0);
}

// A point drawn uniformly in a cell of the list.
geometry::Vector6d point_in(const Workspace& ws, const CellIndex& cell, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  geometry::Vector6d pose = geometry::Vector6d::Zero();
  const double side = ws.resolution_mm * std::ldexp(1.0, cell.level);
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    pose[axis] = ws.position_axes[a]
                     ? ws.origin_mm[axis] + ws.resolution_mm * cell.at[a] + side * unit(rng)
                     : ws.origin_mm[axis];
  }
  for (int k = 0; k < 3; ++k) {
    pose[3 + k] = ws.orientation_min_rad[k] +
                  (ws.orientation_max_rad[k] - ws.orientation_min_rad[k]) * unit(rng);
  }
  return pose;
}

TEST(Workspace, EveryPoseOfAProvenInsideCellIsReachable) {
  // The hexapod over +-5 deg: random points of proven-inside cells, random orientations.
  const machine::Machine machine = test::load_example("hexapod-bit.toml");
  WorkspaceOptions options = at_resolution(machine, 32.0);
  options.orientation_min_rad = Eigen::Vector3d::Constant(geometry::degrees_to_radians(-5.0));
  options.orientation_max_rad = Eigen::Vector3d::Constant(geometry::degrees_to_radians(5.0));
  const Workspace ws = compute_workspace(machine, options);
  ASSERT_GT(ws.inside.size(), 100u);
  EXPECT_TRUE(ws.guaranteed);
  std::mt19937_64 rng(7);
  kinematics::JointVector joints;
  int checked = 0;
  for (int n = 0; n < 20000; ++n) {
    const CellIndex& cell = ws.inside[rng() % ws.inside.size()];
    const geometry::Pose pose = geometry::Pose::from_vector(point_in(ws, cell, rng));
    ASSERT_TRUE(machine.inverse(pose, joints).ok())
        << machine.explain(pose, machine.inverse(pose, joints));
    ++checked;
  }
  EXPECT_EQ(checked, 20000);
  // Every orientation of the range asks more than one: the volume shrinks.
  const Workspace fixed = compute_workspace(machine, at_resolution(machine, 32.0));
  EXPECT_LT(ws.inside_measure, fixed.inside_measure);
  EXPECT_LT(ws.estimate, 0.9 * fixed.estimate);
  // A cell outside at home's orientation is outside for the range: the outer bound shrinks too.
  EXPECT_LE(ws.inside_measure + ws.boundary_measure, fixed.inside_measure + fixed.boundary_measure);
}

// The paper's hexapod with `keys` added to its [kinematics] and its legs' min set to `leg_min_mm`.
machine::Machine hexapod_with(const std::string& keys, double leg_min_mm = 600.0) {
  std::ifstream file(test::example_machine_path("hexapod-bit.toml"));
  std::stringstream text;
  text << file.rdbuf();
  std::string toml = text.str();
  const std::string tool = "tool_length = 30.0\n";
  toml.replace(toml.find(tool), tool.size(), tool + keys + "\n");
  const std::string min = "min = 600.0";
  for (std::size_t at = toml.find(min); at != std::string::npos; at = toml.find(min, at + 1))
    toml.replace(at, min.size(), "min = " + std::to_string(leg_min_mm));
  return machine::parse_machine(toml, "hexapod-limited.toml");
}

// 5000 random points of the proven-inside cells (random orientations of the range) must all be
// accepted by the machine, and no cell proven inside was refused at its middle.
void expect_inside_cells_reachable(const machine::Machine& machine, const Workspace& ws) {
  EXPECT_TRUE(ws.guaranteed);
  EXPECT_EQ(ws.unbounded_refusals, 0);
  ASSERT_FALSE(ws.inside.empty());
  std::mt19937_64 rng(13);
  kinematics::JointVector joints;
  for (int n = 0; n < 5000; ++n) {
    const geometry::Pose pose =
        geometry::Pose::from_vector(point_in(ws, ws.inside[rng() % ws.inside.size()], rng));
    ASSERT_TRUE(machine.inverse(pose, joints).ok())
        << machine.explain(pose, machine.inverse(pose, joints));
  }
}

TEST(Workspace, JointAngleLimitLiftsTheLowestPointAsComputedByHand) {
  // Both joint axes vertical, 30 deg, the platform level: each leg's direction lies within 30 deg
  // of vertical, so with h_i the horizontal offset from base joint i to platform joint i (the
  // same for every tip position on the z axis) the tip at (0, 0, z) needs
  // dz_i = z + tool + p_i.z - a_i.z >= |h_i| / tan 30. The workspace (convex in this cut: an
  // intersection of cones, symmetric under the hexapod's 120 deg turn) is lowest on the axis.
  const machine::Machine machine = hexapod_with(
      "max_joint_angle = 30.0\nbase_joint_axis = [0.0, 0.0, 1.0]\n"
      "platform_joint_axis = [0.0, 0.0, 1.0]",
      100.0);
  const auto& geometry =
      dynamic_cast<const kinematics::HexapodKinematics&>(machine.kinematics()).geometry();
  double lowest = -INFINITY;
  for (std::size_t i = 0; i < 6; ++i) {
    const Eigen::Vector3d offset = geometry.platform_mm[i] - geometry.base_mm[i];
    const double h = offset.head<2>().norm();
    lowest = std::max(lowest, h / std::tan(geometry::degrees_to_radians(30.0)) - 30.0 - offset.z());
  }
  kinematics::JointVector joints;
  ASSERT_TRUE(
      machine.inverse(geometry::Pose{{0.0, 0.0, lowest + 1e-6}, {0.0, 0.0, 0.0}}, joints).ok());
  EXPECT_EQ(machine.inverse(geometry::Pose{{0.0, 0.0, lowest - 1.0}, {0.0, 0.0, 0.0}}, joints).code,
            kinematics::StatusCode::joint_angle);
  const double resolution = 8.0;
  const Workspace ws = compute_workspace(machine, at_resolution(machine, resolution));
  expect_inside_cells_reachable(machine, ws);
  ASSERT_TRUE(ws.extent);
  // The cell holding the lowest point cannot be proven outside; cells far enough below it must
  // be: 4 cells is what the rate bound (about 1/|leg| rad per mm) leaves undecided here.
  EXPECT_LE(ws.extent->min().z(), lowest);
  EXPECT_GE(ws.extent->min().z(), lowest - 4.0 * resolution);
  // No proven-inside cell reaches below the lowest point.
  for (const CellIndex& cell : ws.inside)
    EXPECT_GE(ws.origin_mm.z() + resolution * cell.at[2], lowest);
  // Without the angle limit the same legs reach lower, down to the base plane (platform joints
  // 30 mm above the tip), not into the mirror image below it.
  const machine::Machine free = hexapod_with("", 100.0);
  const Workspace unlimited = compute_workspace(free, at_resolution(free, resolution));
  EXPECT_LT(unlimited.extent->min().z(), lowest - 4.0 * resolution);
  EXPECT_GE(unlimited.extent->min().z(), -30.0 - resolution);
  EXPECT_LT(ws.inside_measure + ws.boundary_measure, unlimited.inside_measure);
}

TEST(Workspace, TheMirrorImageBelowTheBaseIsNoPartOfTheWorkspace) {
  // The paper's hexapod's legs reach a mirror image of its workspace below the base (legs
  // pointing down, platform level), 30 % of its volume before the assembly mode kept home's side
  // of the base plane. Platform joints lie 30 mm above the tip: no kept cell reaches below -30 mm
  // and a cell, with or without joints of 45 deg about the legs' directions at home.
  const machine::Machine free = test::load_example("hexapod-bit.toml");
  const Workspace ws_free = compute_workspace(free, at_resolution(free, 32.0));
  expect_inside_cells_reachable(free, ws_free);
  ASSERT_TRUE(ws_free.extent);
  EXPECT_GT(ws_free.extent->min().z(), -30.0 - 32.0);
  EXPECT_GT(ws_free.limited_by.count("other_assembly"), 0u);
  const machine::Machine machine = hexapod_with("max_joint_angle = 45.0");
  const Workspace ws = compute_workspace(machine, at_resolution(machine, 32.0));
  expect_inside_cells_reachable(machine, ws);
  ASSERT_TRUE(ws.extent);
  EXPECT_GT(ws.extent->min().z(), -30.0 - 32.0);
  EXPECT_LE(ws.inside_measure, ws_free.inside_measure);
}

TEST(Workspace, TheLinuxcncSampleHexapodsBoxIsAboveItsBaseNotInTheMirrorImage) {
  // LinuxCNC's hexapod sample as imported, legs 20..40 in (tests/data): the same leg lengths hold
  // the platform above the base plane z = 0 and its mirror image below; home (z = 20 in) reaches
  // only the first. The largest box was z -637..-381 mm, below the base.
  const machine::Machine machine =
      machine::load_machine(std::filesystem::path(PKM_SOURCE_DIR) / "tests" / "data" /
                            "linuxcnc-hexapod-sample-legs-20-40.toml");
  const double resolution = 8.0;
  const Workspace ws = compute_workspace(machine, at_resolution(machine, resolution));
  expect_inside_cells_reachable(machine, ws);
  ASSERT_TRUE(ws.extent && ws.largest_box);
  // Platform joints at the tip's height: nothing below z = 0 but the cells holding it.
  EXPECT_GE(ws.extent->min().z(), -resolution);
  for (const CellIndex& cell : ws.inside)
    EXPECT_GE(ws.origin_mm.z() + resolution * cell.at[2], 0.0);
  EXPECT_GT(ws.largest_box->min().z(), 0.0);
  EXPECT_GT(ws.largest_box->max().z(), 20.0 * 25.4 - 200.0);
  EXPECT_GT(ws.limited_by.count("other_assembly"), 0u);
  // The mirror image of home, refused with the leg and how far past the plane it is.
  kinematics::JointVector joints;
  const geometry::Pose mirror{{0.0, 0.0, -20.0 * 25.4}, {0.0, 0.0, 0.0}};
  const kinematics::Status status = machine.inverse(mirror, joints);
  EXPECT_EQ(status.code, kinematics::StatusCode::other_assembly);
  EXPECT_NE(machine.explain(mirror, status)
                .find("the platform joint of 'leg0' is 20.0000 in past the base"),
            std::string::npos)
      << machine.explain(mirror, status);
}

TEST(Workspace, LegInterferenceShrinksTheWorkspace) {
  // The paper's 40 mm legs: poses where two legs pass within 40 mm leave the workspace.
  const machine::Machine free = test::load_example("hexapod-bit.toml");
  const machine::Machine machine = hexapod_with("leg_diameter = 40.0");
  const Workspace unlimited = compute_workspace(free, at_resolution(free, 32.0));
  const Workspace ws = compute_workspace(machine, at_resolution(machine, 32.0));
  expect_inside_cells_reachable(machine, ws);
  EXPECT_LT(ws.inside_measure, 0.95 * unlimited.inside_measure);
  EXPECT_GT(ws.limited_by.count("interference"), 0u);
  // Nothing the joint limits refuse comes back.
  EXPECT_LE(ws.inside_measure + ws.boundary_measure,
            unlimited.inside_measure + unlimited.boundary_measure);
}

TEST(Workspace, EveryPointOutsideTheCellsIsRefused) {
  // Points of the grid in neither an inside nor a boundary cell were proven outside: the machine
  // must refuse each (triaglide: joint limits, reach and the assembly mode all decide cells).
  const machine::Machine machine = test::load_example("triaglide.toml");
  const Workspace ws = compute_workspace(machine, at_resolution(machine, 16.0));
  std::set<std::array<std::int32_t, 4>> kept;
  for (const auto* cells : {&ws.inside, &ws.boundary}) {
    for (const CellIndex& cell : *cells)
      kept.insert({cell.at[0], cell.at[1], cell.at[2], cell.level});
  }
  int top = 0;
  for (const CellIndex& cell : ws.inside) top = std::max(top, cell.level);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  kinematics::JointVector joints;
  int outside = 0;
  for (int n = 0; n < 20000; ++n) {
    geometry::Pose pose = machine.home();
    std::array<std::int32_t, 3> index{};
    for (int axis = 0; axis < 3; ++axis) {
      const auto a = static_cast<std::size_t>(axis);
      const double steps = ws.dims[a] * unit(rng);
      pose.position_mm[axis] = ws.origin_mm[axis] + ws.resolution_mm * steps;
      index[a] = static_cast<std::int32_t>(steps);
    }
    bool in_a_cell = false;
    for (int level = 0; level <= top && !in_a_cell; ++level) {
      const auto snap = [&](std::int32_t i) { return (i >> level) << level; };
      in_a_cell = kept.count({snap(index[0]), snap(index[1]), snap(index[2]), level}) > 0;
    }
    if (in_a_cell) continue;
    ++outside;
    ASSERT_FALSE(machine.inverse(pose, joints).ok()) << machine.format_pose(pose);
  }
  EXPECT_GT(outside, 1000);
}

// The fraction of `samples` uniform points of the grid's box where the machine stands.
struct MonteCarlo {
  double volume = 0.0, sigma = 0.0;
};

MonteCarlo monte_carlo(const machine::Machine& machine, const Workspace& ws, int samples) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double box = 1.0;
  for (int axis = 0; axis < 3; ++axis) {
    if (ws.position_axes[static_cast<std::size_t>(axis)])
      box *= ws.resolution_mm * ws.dims[static_cast<std::size_t>(axis)];
  }
  kinematics::JointVector joints;
  int hits = 0;
  for (int n = 0; n < samples; ++n) {
    geometry::Pose pose = machine.home();
    for (int axis = 0; axis < 3; ++axis) {
      const auto a = static_cast<std::size_t>(axis);
      if (ws.position_axes[a]) {
        pose.position_mm[axis] = ws.origin_mm[axis] + ws.resolution_mm * ws.dims[a] * unit(rng);
      }
    }
    hits += machine.inverse(pose, joints).ok() ? 1 : 0;
  }
  const double p = static_cast<double>(hits) / samples;
  return {p * box, std::sqrt(p * (1.0 - p) / samples) * box};
}

class WorkspaceOfEveryExample : public ::testing::TestWithParam<std::string> {};

TEST_P(WorkspaceOfEveryExample, VolumeAgreesWithMonteCarlo) {
  const machine::Machine machine = test::load_example(GetParam());
  // Coarse enough to stay fast: about 160 finest cells across the search box.
  const SearchBox search = search_box(machine, default_options(machine));
  double longest = 0.0, shortest = INFINITY;
  for (int axis = 0; axis < 3; ++axis) {
    if (machine.kinematics().dof().controls(axis)) {
      longest = std::max(longest, search.box.max()[axis] - search.box.min()[axis]);
      shortest = std::min(shortest, search.box.max()[axis] - search.box.min()[axis]);
    }
  }
  // Models whose inverse solves a balance are slow (sampled, or a cable robot's tensions, whose
  // bound solves it at each cell): coarser cells, fewer Monte Carlo samples, a wider
  // statistical error.
  const kinematics::CableTensions* tensions = machine.kinematics().cable_tensions();
  bool slow = tensions != nullptr && tensions->tension_limited();
  for (const auto& constraint : machine_constraints(machine)) slow = slow || !constraint->proven();
  // A thin axis (a Maslow's 60 mm of Z) needs a few cells across.
  const double resolution = std::min(longest / (slow ? 100.0 : 160.0), shortest / 4.0);
  const Workspace ws = compute_workspace(machine, at_resolution(machine, resolution));
  const MonteCarlo mc = monte_carlo(machine, ws, slow ? 20000 : 400000);
  ASSERT_GT(mc.volume, 0.0);
  const double spread = 3.0 * mc.sigma;
  // What the cells claim: inside <= volume <= inside + boundary.
  EXPECT_LE(ws.inside_measure, mc.volume + spread);
  EXPECT_GE(ws.inside_measure + ws.boundary_measure, mc.volume - spread);
  // The estimate within 1 % (plus Monte Carlo's own error).
  std::printf("%s: inside %.6g boundary %.6g estimate %.6g monte carlo %.6g +- %.2g\n",
              GetParam().c_str(), ws.inside_measure, ws.boundary_measure, ws.estimate, mc.volume,
              mc.sigma);
  EXPECT_NEAR(ws.estimate, mc.volume, 0.01 * mc.volume + spread)
      << "inside " << ws.inside_measure << " boundary " << ws.boundary_measure;
}

INSTANTIATE_TEST_SUITE_P(Examples, WorkspaceOfEveryExample,
                         ::testing::ValuesIn(test::example_machine_files()),
                         [](const auto& parameter) { return test::test_name(parameter.param); });

// A cell of pen positions judged by every constraint of the machine: 1 proven inside, -1
// proven outside, 0 neither.
int judge(const machine::Machine& machine, const Eigen::Vector2d& centre,
          const Eigen::Vector2d& half) {
  PoseCell cell;
  cell.centre = machine.home().as_vector();
  cell.centre.head<2>() = centre;
  cell.half.head<2>() = half;
  bool inside = true;
  for (const auto& constraint : machine_constraints(machine)) {
    EXPECT_TRUE(constraint->proven());
    std::vector<Margin> margins(static_cast<std::size_t>(constraint->count()));
    constraint->bound(cell, margins);
    for (const Margin& m : margins) {
      if (m.high < 0.0) return -1;
      inside = inside && m.low > 0.0;
    }
  }
  return inside ? 1 : 0;
}

TEST(Workspace, PulleysPullRegionEndsBelowEachPulleysOuterTangent) {
  // hektor-pulleys.toml: the left belt hangs straight down from its pulley's rightmost point
  // when the pen is at x = r = 6.366 mm (the right one at 100 - r): left of it the right belt
  // would push. Cells clear of it either side are proven; one across it is neither.
  const machine::Machine machine = test::load_example("hektor-pulleys.toml");
  EXPECT_EQ(judge(machine, {6.366 + 0.25, -50.0}, {0.2, 0.5}), 1);
  EXPECT_EQ(judge(machine, {6.366 - 0.25, -50.0}, {0.2, 0.5}), -1);
  EXPECT_EQ(judge(machine, {6.366, -50.0}, {0.2, 0.5}), 0);
  EXPECT_EQ(judge(machine, {100.0 - 6.366 - 0.25, -50.0}, {0.2, 0.5}), 1);
  EXPECT_EQ(judge(machine, {100.0 - 6.366 + 0.25, -50.0}, {0.2, 0.5}), -1);
  const Workspace ws = compute_workspace(machine, at_resolution(machine, 1.0));
  EXPECT_TRUE(ws.guaranteed);
}

TEST(Workspace, WeighedStraightCablesAreGuaranteedAndAgreeWithMonteCarlo) {
  // The gondola of makelangelo.toml on straight cables: its tension limits [0.5, 30] N bound
  // the region; the balance's bounds prove cells (guaranteed), and the estimate agrees with
  // Monte Carlo within 1 %.
  const machine::Machine machine =
      machine::load_machine(std::string(PKM_SOURCE_DIR) + "/tests/data/makelangelo-straight.toml");
  EXPECT_EQ(judge(machine, {0.0, 0.0}, {4.0, 4.0}), 1);     // 1.72 N each, 584 mm of belt
  EXPECT_EQ(judge(machine, {0.0, 700.0}, {4.0, 4.0}), -1);  // above the anchors
  const Workspace ws = compute_workspace(machine, at_resolution(machine, 8.0));
  EXPECT_TRUE(ws.guaranteed);
  const MonteCarlo mc = monte_carlo(machine, ws, 100000);
  const double spread = 3.0 * mc.sigma;
  std::printf(
      "makelangelo-straight: inside %.6g boundary %.6g estimate %.6g monte carlo %.6g +- "
      "%.2g\n",
      ws.inside_measure, ws.boundary_measure, ws.estimate, mc.volume, mc.sigma);
  EXPECT_LE(ws.inside_measure, mc.volume + spread);
  EXPECT_GE(ws.inside_measure + ws.boundary_measure, mc.volume - spread);
  EXPECT_NEAR(ws.estimate, mc.volume, 0.01 * mc.volume + spread);
}

TEST(Workspace, JsonKeepsTheSchemaNames) {
  const machine::Machine machine = biglide();
  const Workspace ws = compute_workspace(machine, at_resolution(machine, 4.0));
  const nlohmann::json doc = to_json(ws);
  EXPECT_EQ(doc["machine"], "biglide");
  EXPECT_TRUE(doc["planar"].get<bool>());
  EXPECT_TRUE(doc.contains("area_mm2"));
  EXPECT_FALSE(doc.contains("volume_mm3"));
  EXPECT_DOUBLE_EQ(doc["area_mm2"]["inside"].get<double>(), ws.inside_measure);
  EXPECT_EQ(doc["cells"]["dims"][2], 1);
  EXPECT_EQ(doc["cells"]["inside"].size(), ws.inside.size());
  EXPECT_EQ(doc["maps"].size(), 2u);
  EXPECT_EQ(doc["maps"][0]["name"], "dexterity");
  const auto& values = doc["maps"][1]["values"];
  EXPECT_EQ(values.size(), static_cast<std::size_t>(doc["maps"][1]["dims"][0].get<int>() *
                                                    doc["maps"][1]["dims"][1].get<int>()));
  // Above the rail the machine cannot stand: null there.
  bool any_null = false;
  for (const auto& v : values) any_null = any_null || v.is_null();
  EXPECT_TRUE(any_null);
}

// The streamed document is the built one, byte for byte; a page's thinned lists keep every k-th
// cell and at most the number asked for.
TEST(Workspace, StreamedJsonIsTheBuiltDocumentAndThinnedListsKeepEveryKth) {
  const machine::Machine machine = biglide();
  const Workspace ws = compute_workspace(machine, at_resolution(machine, 2.0));
  ASSERT_GT(ws.boundary.size(), 100u);
  std::ostringstream streamed;
  write_json(streamed, ws);
  EXPECT_EQ(streamed.str(), to_json(ws).dump());
  const nlohmann::json thin = to_json(ws, 50);
  const auto& boundary = thin["cells"]["boundary"];
  ASSERT_LE(boundary.size(), 50u);
  ASSERT_GE(boundary.size(), 25u);
  const std::size_t every = (ws.boundary.size() + 49) / 50;
  for (std::size_t n = 0; n < boundary.size(); ++n)
    EXPECT_EQ(boundary[n][0].get<int>(), ws.boundary[n * every].at[0]);
  EXPECT_TRUE(to_json(ws, 0)["cells"]["inside"].empty());
}

TEST(Workspace, CellEstimateAgreesWithTheRun) {
  // Hektor (planar: the count doubles with each halving) and the paper's hexapod (3D: four
  // times), each estimated from coarser runs: the cells judged (the bound) within 3 % of the
  // run's, the cells listed (the memory) within 15 % (the hexapod's 11 % low: inside cells merge
  // more at the coarse run).
  struct Case {
    const char* machine;
    double resolution_mm;
  };
  for (const Case c : {Case{"hektor.toml", 0.125}, Case{"hexapod-bit.toml", 16.0}}) {
    const machine::Machine machine = test::load_example(c.machine);
    const WorkspaceOptions options = at_resolution(machine, c.resolution_mm);
    const CellEstimate estimate = estimate_cells(machine, options);
    EXPECT_GT(estimate.from_resolution_mm, c.resolution_mm) << c.machine;
    const Workspace ws = compute_workspace(machine, options);
    const auto listed = static_cast<double>(ws.inside.size() + ws.boundary.size());
    EXPECT_NEAR(estimate.judged / static_cast<double>(ws.cells_judged), 1.0, 0.03) << c.machine;
    EXPECT_NEAR(estimate.listed / listed, 1.0, 0.15) << c.machine;
    EXPECT_EQ(estimate.bytes, 2.0 * estimate.listed * sizeof(CellIndex));
  }
}

TEST(Workspace, ResolutionTooFineIsRefusedBeforeItsWorkNamingOneThatFits) {
  // Issue 26: a resolution too fine grew to gigabytes before the cell bound refused it. Hektor
  // at 1/32 mm would judge some 128,000 cells; under a bound of 20,000 it is refused from the
  // estimate, and the resolution it names runs within the bound.
  const machine::Machine hektor = test::load_example("hektor.toml");
  WorkspaceOptions options = at_resolution(hektor, 0.03125);
  options.max_cells = 20'000;
  double fitting_mm = 0.0;
  try {
    compute_workspace(hektor, options);
    FAIL() << "ran past the bound";
  } catch (const CellBoundError& error) {
    EXPECT_NEAR(error.estimate.judged, 128'534.0, 0.03 * 128'534.0);
    EXPECT_NE(std::string(error.what()).find("more than the bound of 20000 cells"),
              std::string::npos)
        << error.what();
    fitting_mm = error.fitting_resolution_mm;
  }
  ASSERT_GT(fitting_mm, 0.03125);
  options.resolution_mm = fitting_mm;
  const Workspace ws = compute_workspace(hektor, options);
  EXPECT_LE(ws.cells_judged, options.max_cells);
  EXPECT_GT(ws.cells_judged, options.max_cells / 2);  // not far coarser than needed
}

// Each model's own box of tool positions, by hand: the biglide's carriages run 0..300 mm on x and
// its struts are 100 mm; the plotter's cables reach 1200 mm from anchors at x 0 and 1000. A
// formula machine has none.
TEST(Workspace, EachModelAnswersItsReachBoxByHand) {
  const auto reach = [](const machine::Machine& machine) {
    kinematics::JointVector low(static_cast<Eigen::Index>(machine.joints().size()));
    kinematics::JointVector high(low.size());
    for (Eigen::Index j = 0; j < low.size(); ++j) {
      low[j] = machine.joints()[static_cast<std::size_t>(j)].min;
      high[j] = machine.joints()[static_cast<std::size_t>(j)].max;
    }
    return machine.kinematics().tool_position_box(low, high);
  };
  const std::optional<Eigen::AlignedBox3d> glide = reach(biglide());
  ASSERT_TRUE(glide.has_value());
  EXPECT_EQ(glide->min(), Eigen::Vector3d(-100.0, -100.0, -100.0));
  EXPECT_EQ(glide->max(), Eigen::Vector3d(400.0, 100.0, 100.0));
  const std::optional<Eigen::AlignedBox3d> cables = reach(plotter());
  ASSERT_TRUE(cables.has_value());
  EXPECT_EQ(cables->min(), Eigen::Vector3d(-200.0, -1200.0, -1200.0));
  EXPECT_EQ(cables->max(), Eigen::Vector3d(1200.0, 1200.0, 1200.0));
  EXPECT_FALSE(reach(test::load_example("mach3-formula.toml")).has_value());
}

TEST(Workspace, AFormulaMachineOnTwoThreadsWritesOneThreadsDocument) {
  // The threads share one constant machine: the formula model's per-call scratch is per thread.
  const machine::Machine machine = test::load_example("mach3-formula.toml");
  WorkspaceOptions options = at_resolution(machine, 1.0);
  options.threads = 1;
  const std::string one = to_json(compute_workspace(machine, options)).dump();
  options.threads = 2;
  const std::string two = to_json(compute_workspace(machine, options)).dump();
  EXPECT_EQ(one, two);
  EXPECT_NE(one.find("\"inside\""), std::string::npos);
  EXPECT_GT(one.size(), 1000u);
}

TEST(Workspace, RefusesAResolutionThatIsNotALength) {
  const machine::Machine machine = biglide();
  EXPECT_THROW(compute_workspace(machine, at_resolution(machine, 0.0)), std::invalid_argument);
  WorkspaceOptions options = at_resolution(machine, 1e-4);
  options.max_cells = 1000;
  EXPECT_THROW(compute_workspace(machine, options), std::invalid_argument);
}

}  // namespace
}  // namespace pkm::workspace
