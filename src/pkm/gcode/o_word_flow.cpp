// O-word flow: subroutines (defined where first seen, further on in the file, or in a file of
// their own on the subroutine path; called with a scope of parameters), Fanuc-style O-number
// programs called by M98 and ended by M99, if/elseif/else, while, do-while and repeat loops,
// break and continue, each bounded (docs/gcode.md, "Bounds"). Skipping a branch reads on to the
// matching O-word line.
#include <algorithm>
#include <cmath>
#include <system_error>

#include "pkm/gcode/interpreter_state.hpp"

namespace pkm::gcode {

namespace {
// The file a subroutine lives in by itself is its name (o<name>, lower case as read) or number.
std::string file_stem(const std::string& label) {
  if (label.size() >= 2 && label.front() == '<') return label.substr(1, label.size() - 2);
  return label;
}
}  // namespace

void Interpreter::State::execute_o_word(const Block& block) {
  apply_assignments(block);  // LinuxCNC programs set none on O-word lines in practice
  const OWord& o = *block.o_word;
  const std::string& keyword = o.keyword;
  if (keyword == "sub") {
    subroutines.emplace(o.label, Definition{current, false});
    bool with_value = false;
    skip_to(o.label, {"endsub"}, nullptr, o.column, &with_value);
    // LinuxCNC reads the definition's endsub in passing, and its [value] into #<_value>
    // (evaluated with what is defined then, an undefined name as 0): pkm does not evaluate it,
    // so #<_value> cannot be read until a call returns.
    if (with_value) {
      parameters.forget_returned();
    } else {
      parameters.set_returned(std::nullopt);
    }
  } else if (keyword == kProgramNumberKeyword) {
    // A Fanuc program number read in passing (the main program's O1, or a subprogram run into
    // without M98): nothing to do, as in LinuxCNC; M98 finds it.
    subroutines.emplace(o.label, Definition{current, true});
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
  const Mark sub = find_subroutine(o.label, false, o.column);
  require_call_depth("o" + o.label + " call", o.column);
  count_program_iteration(o.column);
  calls.push_back({o.label, next, flow.size(), false, sub, 0, 0, {}});
  parameters.push_scope(o.arguments);
  jump(after(sub));
}

void Interpreter::State::return_from_subroutine(const OWord& o) {
  if (calls.empty()) fail(o.column, "o" + o.label + " " + o.keyword + " outside a subroutine");
  if (calls.back().fanuc) {
    fail(o.column, "o" + o.label + " " + o.keyword + " in O" + calls.back().label +
                       ", an M98 program: M99 ends it");
  }
  parameters.set_returned(o.value);
  leave_call(o.column);
}

void Interpreter::State::leave_call(int column) {
  const Call call = calls.back();
  calls.pop_back();
  flow.resize(std::min(flow.size(), call.flow_depth));
  parameters.pop_scope();
  jump(call.return_to);
  restore_on_return(call.context, column);
}

void Interpreter::State::call_fanuc_program(const Block& block, const Code& m98) {
  const auto& p = block.word('p');
  if (!p) fail(m98.column, "M98 needs a P word: the number of the O program to call");
  if (!(p->value >= 0.0 && p->value < 1e9) || p->value != std::floor(p->value)) {
    fail(p->column, "M98 P" + written_number(p->value) +
                        ": the program number must be a whole number from 0 to 999999999");
  }
  long runs = 1;
  if (const auto& l = block.word('l')) {
    if (!(l->value >= 0.0) || l->value != std::floor(l->value)) {
      fail(l->column, "M98 L" + written_number(l->value) +
                          ": the repeat count must be a whole "
                          "number of 0 or more");
    }
    if (l->value > static_cast<double>(options.max_loop_iterations)) {
      fail(l->column, "M98 L" + written_number(l->value) + ": more than the " +
                          std::to_string(options.max_loop_iterations) +
                          " iterations one loop may make");
    }
    runs = std::lround(l->value);
  }
  if (runs == 0) return;  // M98 L0 calls nothing, as in LinuxCNC
  const std::string label = std::to_string(std::lround(p->value));
  const Mark program = find_subroutine(label, true, p->column);
  require_call_depth("M98 P" + label, m98.column);
  count_program_iteration(m98.column);
  calls.push_back({label, next, flow.size(), true, program, runs - 1, 1, {}});
  parameters.push_scope_sharing_numbered();
  jump(after(program));
}

void Interpreter::State::return_from_fanuc_program(const Block& block, const Code& m99) {
  parameters.set_returned(std::nullopt);  // M99 returns no value, as LinuxCNC reads it
  if (calls.empty()) {
    // M99 in the main program ends it, as M2 does (LinuxCNC's default: no endless loop).
    release_compensation(m99.column);
    end_program(block);
    return;
  }
  Call& call = calls.back();
  if (!call.fanuc) {
    fail(m99.column, "M99 in o" + call.label + ", a subroutine called by o" + call.label +
                         " call: endsub or return ends it");
  }
  if (call.repeats == 0) {
    leave_call(m99.column);
    return;
  }
  // M98 L: the program runs again, with fresh local names and no saved modes (LinuxCNC returns
  // and calls again: M73's modes are restored in between).
  const SavedContext leaving = call.context;
  call.context = {};
  restore_on_return(leaving, m99.column);
  --call.repeats;
  if (++call.iterations > options.max_loop_iterations) {
    fail(m99.column, "O" + call.label + " ran more than " +
                         std::to_string(options.max_loop_iterations) + " times");
  }
  count_program_iteration(m99.column);
  flow.resize(std::min(flow.size(), call.flow_depth));
  parameters.pop_scope();
  parameters.push_scope_sharing_numbered();
  jump(after(call.start));
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
                                 std::string* found_keyword, int column, bool* with_value) {
  const int start_line = current.line;
  std::string_view line;
  while (read_line(line)) {
    std::string found_label;
    const std::string keyword = o_word_keyword(line, &found_label, with_value);
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
  throw GcodeError(file_name(), start_line, column, "o" + label + ": no matching " + names);
}

Interpreter::State::Mark Interpreter::State::find_subroutine(const std::string& label, bool fanuc,
                                                             int column) {
  auto known = subroutines.find(label);
  if (known == subroutines.end()) {
    // Not yet seen: its definition further on in this file, or a file of its own.
    std::optional<Mark> found = scan_for_definition(next, label);
    if (!found) found = open_subroutine_file(label, column);
    if (!found) {
      std::string looked = "in " + file_name();
      for (const std::filesystem::path& directory : subroutine_directories()) {
        looked += ", " + (directory / (file_stem(label) + ".ngc")).string();
      }
      fail(column, std::string(fanuc ? "unknown program O" : "unknown subroutine o") + label +
                       " (looked " + looked + ")");
    }
    known = subroutines.find(label);
  }
  if (known->second.fanuc != fanuc) {
    fail(column, fanuc ? "o" + label + " is a subroutine (o" + label + " sub): call it with o" +
                             label + " call, not M98"
                       : "O" + label + " is a Fanuc-style program: call it with M98 P" + label +
                             ", not o" + label + " call");
  }
  return known->second.mark;
}

std::optional<Interpreter::State::Mark> Interpreter::State::scan_for_definition(
    const Mark& mark, const std::string& label) {
  const Mark saved_next = next, saved_current = current;
  jump(mark);
  std::optional<Mark> found;
  std::string_view line;
  while (!found && read_line(line)) {
    std::string name;
    const std::string keyword = o_word_keyword(line, &name);
    const bool fanuc = keyword == kProgramNumberKeyword;
    if (keyword != "sub" && !fanuc) continue;
    subroutines.emplace(name, Definition{current, fanuc});
    if (name == label) found = subroutines[label].mark;
  }
  jump(saved_next);
  current = saved_current;
  return found;
}

std::vector<std::filesystem::path> Interpreter::State::subroutine_directories() const {
  std::vector<std::filesystem::path> directories{files[0]->path.parent_path()};
  if (directories[0].empty()) directories[0] = ".";
  directories.insert(directories.end(), options.subroutine_path.begin(),
                     options.subroutine_path.end());
  return directories;
}

std::optional<Interpreter::State::Mark> Interpreter::State::open_subroutine_file(
    const std::string& label, int column) {
  const std::string stem = file_stem(label);
  // A name that is no plain file name (o<../x>) is looked for nowhere.
  if (stem.empty() || stem.find('/') != std::string::npos || stem == "." || stem == "..") {
    return std::nullopt;
  }
  for (const std::filesystem::path& directory : subroutine_directories()) {
    const std::filesystem::path path = directory / (stem + ".ngc");
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) continue;
    if (files.size() >= kMaxSubroutineFiles) {
      fail(column, "more than " + std::to_string(kMaxSubroutineFiles) +
                       " subroutine files opened by one program");
    }
    files.push_back(std::make_unique<SourceFile>(path));
    if (!files.back()->lines.is_open()) {
      fail(column, path.string() + ": " + cannot_open_reason(path, false));
    }
    const std::optional<Mark> found = scan_for_definition({0, 1, files.size() - 1}, label);
    if (!found) {
      fail(column,
           path.string() + " has no " +
               (label.front() == '<' ? "o" + label + " sub" : "o" + label + " sub or O" + label) +
               " line");
    }
    return found;
  }
  return std::nullopt;
}

void Interpreter::State::count_loop_iteration(Frame& loop, int column) {
  if (++loop.iterations > options.max_loop_iterations) {
    throw GcodeError(file_name(), loop.start.line, 0,
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

void Interpreter::State::require_call_depth(const std::string& what, int column) const {
  if (calls.size() >= kMaxCallDepth) {
    fail(column, what + ": subroutine calls nested deeper than " + std::to_string(kMaxCallDepth) +
                     " (LinuxCNC's limit)");
  }
}

}  // namespace pkm::gcode
