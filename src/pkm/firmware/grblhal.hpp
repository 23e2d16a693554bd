// The grblhal target (docs/firmware-grblhal.md): a two-cable wall plotter as grblHAL's WallPlotter
// kinematics holds it (grblHAL/core kinematics/wall_plotter.c), written as `$` settings and read
// back. grblHAL's frame has its origin at motor A (X), motor B (Y) on +x and the pen on +y (y
// measured from the motor line toward the pen): against a pkmkit wall plotter (left anchor first,
// pen below, y up) it is the machine's frame turned 180 deg about z. No grblHAL setting turns it
// back, so the target refuses; `grblhal_write(..., GrblhalFrameTurn::allow)` writes the turned
// frame (G54 then reads the machine's -x, -y) for a caller that says so.
#pragma once

#include <string>
#include <string_view>

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {

enum class GrblhalFrameTurn {
  refuse,  // the target's own: ExportRefused naming the turn
  allow,   // write it: G54 X Y are the machine's -x -y (the file's header and warnings say so)
};

// The `$` settings of `machine` (a two-cable wall plotter) for grblHAL's WallPlotter.
ExportedFile grblhal_write(const FirmwareMachine& machine, const ExportContext& context,
                           GrblhalFrameTurn turn);

// The wall plotter a grblHAL settings file (`$N=value` lines, comments, G10 L2 P1) describes.
// Throws FirmwareFileError ("file:line: $N: why") for a number that is not one or a missing
// setting the kinematics needs.
machine::ImportedMachine grblhal_read(std::string_view text, const std::string& source);

Target grblhal_target();

}  // namespace pkm::firmware
