// The job's commands to the machine that are neither motion nor the spindle's turning and the
// coolant: pauses (M0, M1, M60), tool selection and change (T, M6), spindle orientation (M19),
// the override switches (M48-M53), digital and analog I/O (M62-M68) and user M-codes
// (M100-M199), each as the G-code that gives it. post
// carries them into a joint program by this text and verify finds them there by it.
#pragma once

#include <string>

#include "pkm/gcode/canon.hpp"

namespace pkm::gcode {

// "M0", "M1", "M60", "T2", "M6", "M19 R90 P0", "M19 Q1.5", "M49", "M62 P1", "M66 P0 L3 Q2.5",
// "M101 P2 Q3"; "" for a command of another kind.
std::string machine_command_text(const Canon& canon);

// The number of such a command's M code (62 for "M62 P1"), -1 for T and for other text.
int machine_command_m_number(const std::string& text);

}  // namespace pkm::gcode
