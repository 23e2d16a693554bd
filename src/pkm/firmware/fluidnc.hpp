// The fluidnc target (docs/firmware-fluidnc.md): FluidNC's config.yaml `kinematics:` and `axes:`
// sections for a two-cable wall plotter (FluidNC's WallPlotter), a rotary delta (FluidNC's
// parallel_delta) or Maslow 4's belts (Maslow's FluidNC fork's MaslowKinematics, in its
// maslow.yaml), and the machine such a file describes.
#pragma once

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

Target fluidnc_target();

// The writer and the reader the target holds (fluidnc.cpp, fluidnc_reader.cpp).
ExportedFile write_fluidnc(const FirmwareMachine& machine, const ExportContext& context);
machine::ImportedMachine read_fluidnc(std::string_view text, const std::string& source);

// Where FluidNC's WallPlotter starts: it cannot home and takes the pen to be at its frame's
// origin at power-on. pkmkit puts that origin at the machine's home pose (mm): FluidNC's frame
// is the machine file's less `home`, and the startup line restores the machine file's frame as
// G54 work coordinates. Written and read as this G-code line.
std::string fluidnc_startup_line(double home_x_mm, double home_y_mm, const double* home_z_mm);

// Maslow's origin: the crossing of the diagonals tr-bl and tl-br of its corners (tl, tr, bl, br;
// x y, mm), as MaslowKinematics::calculateCenter finds it.
Eigen::Vector2d maslow_centre(const std::vector<Eigen::Vector3d>& corners_mm);

}  // namespace pkm::firmware
