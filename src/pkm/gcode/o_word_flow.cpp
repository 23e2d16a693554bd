// O-word flow: subroutines (defined where first seen, called with a scope of parameters),
// if/elseif/else, while, do-while and repeat loops, break and continue, each bounded
// (docs/gcode.md, "Bounds"). Skipping a branch reads on to the matching O-word line.
#include <algorithm>
#include <cmath>

#include "pkm/gcode/interpreter_state.hpp"

namespace pkm::gcode {

void Interpreter::State::execute_o_word(const Block& block) {
  apply_assignments(block);  // LinuxCNC programs set none on O-word lines in practice
  const OWord& o = *block.o_word;
  const std::string& keyword = o.keyword;
  if (keyword == "sub") {
    subroutines.emplace(o.label, current);
    skip_to(o.label, {"endsub"}, nullptr, o.column);
  } else if (keyword == "call") {
    call_subroutine(o);
  } else if (keyword == "endsub" || keyword == "return") {
    return_from_subroutine(o);
  } else if (keyword == "if") {
    o_if(o);
  } else if (keyword == "elseif" || keyword == "else") {
    o_else(o);
  } else if (keyword == "endif") {
    if (innermost_is(Frame::Type::if_, o.label)) flow.pop_back();
  } else if (keyword == "do") {
    flow.push_back({Frame::Type::do_, o.label, current, 0, false});
  } else if (keyword == "while") {
    o_while(o);
  } else if (keyword == "endwhile") {
    o_endwhile(o);
  } else if (keyword == "repeat") {
    o_repeat(o);
  } else if (keyword == "endrepeat") {
    o_endrepeat(o);
  } else if (keyword == "break" || keyword == "continue") {
    o_break_or_continue(o);
  }
}

double Interpreter::State::o_value(const OWord& o) const {
  if (!o.value) fail(o.column, "o" + o.label + " " + o.keyword + " needs a [value]");
  return *o.value;
}

void Interpreter::State::call_subroutine(const OWord& o) {
  const Mark sub = find_subroutine(o.label, o.column);
  require_call_depth(o);
  count_program_iteration(o.column);
  calls.push_back({o.label, next, flow.size()});
  parameters.push_scope(o.arguments);
  jump(after(sub));
}

void Interpreter::State::return_from_subroutine(const OWord& o) {
  if (calls.empty()) fail(o.column, "o" + o.label + " " + o.keyword + " outside a subroutine");
  if (o.value) parameters.set_named("_value", *o.value);
  const Call call = calls.back();
  calls.pop_back();
  flow.resize(std::min(flow.size(), call.flow_depth));
  parameters.pop_scope();
  jump(call.return_to);
}

void Interpreter::State::o_if(const OWord& o) {
  if (o_value(o) != 0.0) {
    flow.push_back({Frame::Type::if_, o.label, current, 0, true});
    return;
  }
  flow.push_back({Frame::Type::if_, o.label, current, 0, false});
  // Find the branch that runs: elseif (re-evaluated when reached), else, or endif.
  std::string keyword;
  skip_to(o.label, {"elseif", "else", "endif"}, &keyword, o.column);
  jump(current);  // execute that line itself
}

void Interpreter::State::o_else(const OWord& o) {
  if (!innermost_is(Frame::Type::if_, o.label)) {
    fail(o.column, "o" + o.label + " " + o.keyword + " without its if");
  }
  Frame& frame = flow.back();
  if (frame.taken) {
    skip_to(o.label, {"endif"}, nullptr, o.column);
    flow.pop_back();
  } else if (o.keyword == "else" || o_value(o) != 0.0) {
    frame.taken = true;
  } else {
    skip_to(o.label, {"elseif", "else", "endif"}, nullptr, o.column);
    jump(current);
  }
}

void Interpreter::State::o_while(const OWord& o) {
  if (innermost_is(Frame::Type::do_, o.label)) {
    // The end of a do-while loop.
    if (o_value(o) != 0.0) {
      count_loop_iteration(flow.back(), o.column);
      jump(after(flow.back().start));
    } else {
      flow.pop_back();
    }
  } else if (o_value(o) != 0.0) {
    if (!innermost_is(Frame::Type::while_, o.label)) {
      flow.push_back({Frame::Type::while_, o.label, current, 0, false});
    }
  } else {
    if (innermost_is(Frame::Type::while_, o.label)) flow.pop_back();
    skip_to(o.label, {"endwhile"}, nullptr, o.column);
  }
}

void Interpreter::State::o_endwhile(const OWord& o) {
  if (!innermost_is(Frame::Type::while_, o.label)) {
    fail(o.column, "o" + o.label + " endwhile without its while");
  }
  count_loop_iteration(flow.back(), o.column);
  jump(flow.back().start);  // re-evaluates the condition
}

void Interpreter::State::o_repeat(const OWord& o) {
  const double wanted = o_value(o);
  if (wanted > static_cast<double>(options.max_loop_iterations)) {
    fail(o.column, "o" + o.label + " repeat [" + written_number(wanted) + "]: more than the " +
                       std::to_string(options.max_loop_iterations) +
                       " iterations one loop may make");
  }
  const long count = std::lround(wanted);
  if (count <= 0) {
    skip_to(o.label, {"endrepeat"}, nullptr, o.column);
  } else {
    flow.push_back({Frame::Type::repeat, o.label, current, count, false});
  }
}

void Interpreter::State::o_endrepeat(const OWord& o) {
  if (!innermost_is(Frame::Type::repeat, o.label)) {
    fail(o.column, "o" + o.label + " endrepeat without its repeat");
  }
  if (--flow.back().remaining > 0) {
    count_loop_iteration(flow.back(), o.column);
    jump(after(flow.back().start));
  } else {
    flow.pop_back();
  }
}

void Interpreter::State::o_break_or_continue(const OWord& o) {
  while (!flow.empty() && flow.back().label != o.label) flow.pop_back();
  if (flow.empty() || flow.back().type == Frame::Type::if_) {
    fail(o.column, "o" + o.label + " " + o.keyword + " outside its loop");
  }
  const Frame frame = flow.back();
  if (o.keyword == "break") {
    flow.pop_back();
    const char* end = frame.type == Frame::Type::repeat ? "endrepeat"
                      : frame.type == Frame::Type::do_  ? "while"
                                                        : "endwhile";
    skip_to(o.label, {end}, nullptr, o.column);
  } else if (frame.type == Frame::Type::while_) {
    count_loop_iteration(flow.back(), o.column);
    jump(frame.start);
  } else {
    // A repeat continues at its endrepeat, a do at its while: both count the round there.
    skip_to(o.label, {frame.type == Frame::Type::repeat ? "endrepeat" : "while"}, nullptr,
            o.column);
    jump(current);
  }
}

void Interpreter::State::skip_to(const std::string& label,
                                 std::initializer_list<std::string_view> keywords,
                                 std::string* found_keyword, int column) {
  const int start_line = current.line;
  std::string_view line;
  while (read_line(line)) {
    std::string found_label;
    const std::string keyword = o_word_keyword(line, &found_label);
    if (keyword.empty() || found_label != label) continue;
    for (const std::string_view wanted : keywords) {
      if (keyword == wanted) {
        if (found_keyword != nullptr) *found_keyword = keyword;
        return;
      }
    }
  }
  std::string names;
  for (const std::string_view k : keywords) names += (names.empty() ? "" : "/") + std::string(k);
  throw GcodeError(file_name, start_line, column, "o" + label + ": no matching " + names);
}

Interpreter::State::Mark Interpreter::State::find_subroutine(const std::string& label, int column) {
  const auto known = subroutines.find(label);
  if (known != subroutines.end()) return known->second;
  // Not yet seen: look for its definition further on, then come back.
  const Mark saved_next = next, saved_current = current;
  std::string_view line;
  while (read_line(line)) {
    std::string found;
    if (o_word_keyword(line, &found) == "sub") {
      subroutines.emplace(found, current);
      if (found == label) {
        jump(saved_next);
        current = saved_current;
        return subroutines[label];
      }
    }
  }
  jump(saved_next);
  current = saved_current;
  fail(column, "unknown subroutine o" + label);
}

void Interpreter::State::count_loop_iteration(Frame& loop, int column) {
  if (++loop.iterations > options.max_loop_iterations) {
    throw GcodeError(file_name, loop.start.line, 0,
                     "the loop o" + loop.label + " went round more than " +
                         std::to_string(options.max_loop_iterations) +
                         " times (the bound on one loop: an endless loop?)");
  }
  count_program_iteration(column);
}

void Interpreter::State::count_program_iteration(int column) {
  if (++program_iterations > options.max_program_iterations) {
    fail(column, "the program made more than " + std::to_string(options.max_program_iterations) +
                     " loop iterations, subroutine calls and canned-cycle holes and pecks "
                     "(the bound on a whole program)");
  }
}

void Interpreter::State::require_call_depth(const OWord& o) const {
  if (calls.size() >= kMaxCallDepth) {
    fail(o.column, "o" + o.label + " call: subroutine calls nested deeper than " +
                       std::to_string(kMaxCallDepth) + " (LinuxCNC's limit)");
  }
}

}  // namespace pkm::gcode
