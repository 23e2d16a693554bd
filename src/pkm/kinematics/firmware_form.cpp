#include "pkm/kinematics/firmware_form.hpp"
#include <algorithm>

#include <cstdio>
#include <stdexcept>

#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/kinematics/cable_robot.hpp"
#include "pkm/kinematics/glide.hpp"
#include "pkm/kinematics/rotary_delta.hpp"

namespace pkm::kinematics {
namespace {

struct FormName {
  const char* operator()(const WallPlotterForm&) const { return "two-cable wall plotter"; }
  const char* operator()(const LinearDeltaForm&) const { return "linear delta"; }
  const char* operator()(const RotaryDeltaForm&) const { return "rotary delta"; }
  const char* operator()(const CableRobotForm& form) const {
    return has_swivel_arms(form) ? "cable robot on swivel arms" : "cable robot";
  }
};

// Each form as the pkmkit model that computes it.
struct FormModel {
  const PassThroughAxes& passthrough;

  std::unique_ptr<Kinematics> operator()(const WallPlotterForm& form) const {
    CablePlotterGeometry geometry;
    geometry.anchors_mm = form.anchors_mm;
    geometry.cable_offsets_mm = form.cable_offsets_mm;
    return std::make_unique<CablePlotterKinematics>(geometry, passthrough);
  }
  // A rail at the column, its reading 0 where the carriage is `carriage_offset` below the tool's
  // height, the rod's ends folded into the column (attach 0).
  std::unique_ptr<Kinematics> operator()(const LinearDeltaForm& form) const {
    std::vector<GlideRail> rails;
    for (const LinearDeltaTower& tower : form.towers) {
      GlideRail rail;
      rail.origin_mm =
          Eigen::Vector3d(tower.column_mm.x(), tower.column_mm.y(), 0.0 - tower.carriage_offset_mm);
      rail.direction = Eigen::Vector3d::UnitZ();
      rail.strut_mm = tower.rod_mm;
      rails.push_back(rail);
    }
    return std::make_unique<GlideKinematics>(std::move(rails), geometry::Dof::translation(),
                                             passthrough);
  }
  std::unique_ptr<Kinematics> operator()(const RotaryDeltaForm& form) const {
    RotaryDeltaGeometry geometry;
    geometry.base_radius_mm = form.base_radius_mm;
    geometry.arm_length_mm = form.arm_length_mm;
    geometry.forearm_length_mm = form.forearm_length_mm;
    geometry.platform_radius_mm = form.platform_radius_mm;
    return std::make_unique<RotaryDeltaKinematics>(geometry, passthrough);
  }
  std::unique_ptr<Kinematics> operator()(const CableRobotForm& form) const {
    if (form.cable_offsets_mm.size() != form.anchors_mm.size()) {
      throw std::invalid_argument("cable robot form: one cable offset per anchor");
    }
    CableRobotGeometry geometry;
    if (!form.swivel_arms_mm.empty() && form.swivel_arms_mm.size() != form.anchors_mm.size()) {
      throw std::invalid_argument("cable robot form: one swivel arm per anchor");
    }
    geometry.planar = form.planar;
    geometry.cables_follow_z = form.cables_follow_z;
    for (std::size_t i = 0; i < form.anchors_mm.size(); ++i) {
      RobotCable cable;
      cable.anchor_mm = form.anchors_mm[i];
      cable.offset_mm = form.cable_offsets_mm[i];
      if (!form.swivel_arms_mm.empty()) cable.swivel_arm_mm = form.swivel_arms_mm[i];
      geometry.cables.push_back(cable);
    }
    return std::make_unique<CableRobotKinematics>(std::move(geometry), passthrough);
  }
};

}  // namespace

bool has_swivel_arms(const CableRobotForm& form) {
  return form.cables_follow_z || std::any_of(form.swivel_arms_mm.begin(), form.swivel_arms_mm.end(),
                                             [](double arm) { return arm != 0.0; });
}

std::string loss_text(const char* format, double value) {
  char text[256];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

const char* form_name(const FormGeometry& geometry) {
  return std::visit(FormName{}, geometry);
}

std::unique_ptr<Kinematics> make_form_kinematics(const FormGeometry& geometry,
                                                 const PassThroughAxes& passthrough) {
  return std::visit(FormModel{passthrough}, geometry);
}

std::optional<FirmwareForm> Kinematics::firmware_form() const {
  return std::nullopt;
}

}  // namespace pkm::kinematics
