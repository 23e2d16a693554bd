// What ignoring each effect of a cable machine as built costs, on the Maslow frame
// (examples/machines/maslow-frame.toml): drive the machine with a model that leaves the effect
// out, and see where the full model puts the bit. The numbers printed here are the ones in
// docs/cable-machines.md ("What each effect costs on a Maslow").
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>

#include "pkm/kinematics/cable_plotter.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

// The sheet, 2438.4 x 1219.2 mm, 463 mm below the motors, centred between them.
constexpr double kSheetLeft = 270.0, kSheetRight = 2708.4, kSheetTop = -463.0,
                 kSheetBottom = -1682.2;

const kinematics::CablePlotterKinematics& full_model(const machine::Machine& machine) {
  return dynamic_cast<const kinematics::CablePlotterKinematics&>(machine.kinematics());
}

// Where the full machine puts the bit when the joints come from `reduced` at `target`.
Eigen::Vector2d drawn(const kinematics::CablePlotterKinematics& full,
                      const kinematics::CablePlotterKinematics& reduced,
                      const Eigen::Vector2d& target) {
  kinematics::JointVector joints;
  const geometry::Pose pose = geometry::Pose::from_mm_deg(target.x(), target.y(), 0.0);
  EXPECT_TRUE(reduced.inverse_within(pose, joints, false).ok());
  geometry::Pose found = pose;
  EXPECT_TRUE(full.forward(joints, found).ok());
  return found.position_mm.head<2>();
}

struct EffectCost {
  double worst_mm = 0.0;          // largest distance from the target over the sheet
  double worst_per_500_mm = 0.0;  // largest error in the length of a 500 mm horizontal line
};

// The targets: a 9 x 5 grid over the sheet.
std::vector<Eigen::Vector2d> sheet_grid() {
  std::vector<Eigen::Vector2d> grid;
  for (int row = 0; row <= 4; ++row) {
    for (int column = 0; column <= 8; ++column) {
      grid.emplace_back(kSheetLeft + (kSheetRight - kSheetLeft) * column / 8.0,
                        kSheetTop + (kSheetBottom - kSheetTop) * row / 4.0);
    }
  }
  return grid;
}

EffectCost cost_of_ignoring(const kinematics::CablePlotterKinematics& full,
                            const kinematics::CablePlotterGeometry& without,
                            std::vector<double>* errors = nullptr) {
  const kinematics::CablePlotterKinematics reduced(without, full.passthrough());
  EffectCost cost;
  for (const Eigen::Vector2d& target : sheet_grid()) {
    const double error = (drawn(full, reduced, target) - target).norm();
    cost.worst_mm = std::max(cost.worst_mm, error);
    if (errors) errors->push_back(error);
    if (target.x() + 500.0 <= kSheetRight) {
      const Eigen::Vector2d end = target + Eigen::Vector2d(500.0, 0.0);
      const double length = (drawn(full, reduced, end) - drawn(full, reduced, target)).norm();
      cost.worst_per_500_mm = std::max(cost.worst_per_500_mm, std::abs(length - 500.0));
    }
  }
  return cost;
}

// The cable offsets a calibration would find for the reduced model (least squares over the
// grid, Gauss-Newton): what is left is what no offset can absorb.
kinematics::CablePlotterGeometry with_best_offsets(const kinematics::CablePlotterKinematics& full,
                                                   kinematics::CablePlotterGeometry reduced) {
  const std::vector<Eigen::Vector2d> grid = sheet_grid();
  const auto residuals = [&](const kinematics::CablePlotterGeometry& geometry) {
    const kinematics::CablePlotterKinematics model(geometry, full.passthrough());
    Eigen::VectorXd r(2 * grid.size());
    for (std::size_t k = 0; k < grid.size(); ++k) {
      r.segment<2>(2 * k) = drawn(full, model, grid[k]) - grid[k];
    }
    return r;
  };
  for (int iteration = 0; iteration < 6; ++iteration) {
    const Eigen::VectorXd r = residuals(reduced);
    Eigen::MatrixXd jacobian(r.size(), 2);
    for (int cable = 0; cable < 2; ++cable) {
      kinematics::CablePlotterGeometry shifted = reduced;
      shifted.cable_offsets_mm[cable] += 1e-3;
      jacobian.col(cable) = (residuals(shifted) - r) / 1e-3;
    }
    const Eigen::Vector2d step = jacobian.colPivHouseholderQr().solve(-r);
    reduced.cable_offsets_mm[0] += step[0];
    reduced.cable_offsets_mm[1] += step[1];
  }
  return reduced;
}

TEST(CableEffects, WhatIgnoringEachCostsOnAMaslowFrame) {
  const machine::Machine machine = test::load_example("maslow-frame.toml");
  const kinematics::CablePlotterKinematics& full = full_model(machine);
  const kinematics::CablePlotterGeometry& g = full.geometry();
  const auto without = [&](const std::function<void(kinematics::CablePlotterGeometry&)>& change) {
    kinematics::CablePlotterGeometry reduced = g;
    change(reduced);
    return reduced;
  };
  struct Effect {
    const char* name;
    kinematics::CablePlotterGeometry geometry;
    double at_least_mm, at_most_mm;  // the range the worst error must fall in, offsets refitted
  };
  const Effect effects[] = {
      {"sprocket wrap (pulley_radius 0)",
       without([](kinematics::CablePlotterGeometry& r) { r.pulley_radius_mm = 0.0; }), 0.1, 30.0},
      {"sled tilt (chains tied at the bit)", without([](kinematics::CablePlotterGeometry& r) {
         r.attach_mm = {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
       }),
       5.0, 400.0},
      {"chain sag (cable_density 0)",
       without([](kinematics::CablePlotterGeometry& r) { r.cable_density_kg_per_m = 0.0; }), 0.5,
       30.0},
      {"chain stretch (unstretchable)",
       without([](kinematics::CablePlotterGeometry& r) { r.cable_stretch_mm_per_m_per_N = 0.0; }),
       0.05, 10.0},
      {"all (the ideal model)", kinematics::CablePlotterGeometry::level(g.anchors_mm[1].x()), 5.0,
       400.0},
  };
  std::printf("[ effects  ] %-36s %10s %10s %10s %10s\n", "ignoring", "worst", "per 500", "refit",
              "refit/500");
  for (const Effect& effect : effects) {
    const EffectCost raw = cost_of_ignoring(full, effect.geometry);
    std::vector<double> errors;
    const EffectCost refit =
        cost_of_ignoring(full, with_best_offsets(full, effect.geometry), &errors);
    std::printf("[ effects  ] %-36s %10.3f %10.3f %10.3f %10.3f\n", effect.name, raw.worst_mm,
                raw.worst_per_500_mm, refit.worst_mm, refit.worst_per_500_mm);
    EXPECT_GE(refit.worst_mm, effect.at_least_mm) << effect.name;
    EXPECT_LE(refit.worst_mm, effect.at_most_mm) << effect.name;
    EXPECT_LE(refit.worst_mm, raw.worst_mm + 1e-9) << effect.name;
    if (std::string(effect.name).rfind("all", 0) != 0) continue;
    for (std::size_t row = 0; row < 5; ++row) {  // the ideal model's map, offsets refitted
      std::printf("[ map      ] y %8.1f:", kSheetTop + (kSheetBottom - kSheetTop) * row / 4.0);
      for (std::size_t column = 0; column < 9; ++column) {
        std::printf(" %6.1f", errors[row * 9 + column]);
      }
      std::printf("\n");
    }
  }
}

}  // namespace
}  // namespace pkm
