// The interpreter's run: lines read from the program, events, '%' and assignments; each line's
// block handed to execute_block or execute_o_word (interpreter_state.hpp lists the rooms).
#include "pkm/gcode/interpreter.hpp"

#include <system_error>

#include "pkm/gcode/interpreter_state.hpp"

namespace pkm::gcode {

Interpreter::State::State(const std::filesystem::path& path, const InterpreterOptions& opts,
                          std::vector<Warning>& warns)
    : options(opts), warnings(warns) {
  files.push_back(std::make_unique<SourceFile>(path));
  reading = &files[0]->lines;
  if (!files[0]->lines.is_open()) {
    throw GcodeError(path.string(), 0, 0, cannot_open_reason(path, false));
  }
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) {
    throw GcodeError(path.string(), 0, 0, cannot_open_reason(path, true));
  }
  // G54 offsets start at zero; #5220 holds the active coordinate system.
  parameters.set_numbered(5220, 1.0);
  pos = canon_pos = options.start_position;
}

void Interpreter::State::start(const CanonSink& output) {
  sink = &output;
  checked_sink = [this](const Canon& canon) {
    if (!all_finite(canon)) not_finite(canon);
    (*sink)(canon);
  };
  compensation.reset(checked_sink);
}

void Interpreter::State::run(const CanonSink& output) {
  start(output);
  std::string_view line;
  while (next_line(line)) execute(line);
  finish();
}

bool Interpreter::State::step() {
  std::string_view line;
  if (next_line(line)) {
    execute(line);
    return true;
  }
  finish();
  return false;
}

bool Interpreter::State::next_line(std::string_view& line) {
  while (!ended && read_line(line)) {
    if (first_content) {
      const auto first = line.find_first_not_of(" \t");
      if (first == std::string::npos) continue;
      first_content = false;
      if (line[first] == '%') {
        percent_program = true;
        continue;
      }
    }
    return true;
  }
  return false;
}

void Interpreter::State::cannot_read() const {
  if (files[current.file]->lines.too_long()) {
    fail(0, "line longer than " + std::to_string(kMaxLineBytes) +
                " bytes, the longest the interpreter reads");
  }
  fail(0, "cannot read the program");
}

Interpreter::State::Mark Interpreter::State::after(const Mark& mark) {
  const Mark saved_next = next, saved_current = current;
  jump(mark);
  std::string_view ignored;
  read_line(ignored);
  const Mark result = next;
  jump(saved_next);
  current = saved_current;
  return result;
}

void Interpreter::State::finish() {
  if (!ended && !saw_end) {
    // The moves compensation still holds are part of the program (rs274 would drop them).
    release_compensation(1);
    warnings.push_back({current.line,
                        "program has no M2, M30 or closing %: ended at the end of "
                        "the file"});
    Block none;
    emit(CanonKind::program_end, none);
  }
  ended = true;
}

bool Interpreter::State::is_event_line(std::string_view line) {
  const auto first = line.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return false;
  const std::string_view trimmed = line.substr(first, line.find_last_not_of(" \t\r") - first + 1);
  for (const std::string& event_line : options.event_lines) {
    if (trimmed != event_line) continue;
    Canon event = make(CanonKind::event, Block{});
    event.text = std::string(trimmed);
    emit(event);
    return true;
  }
  return false;
}

void Interpreter::State::execute_line(std::string_view line) {
  Block& block = block_;
  // #5420..#5428: the current position in the active coordinate system, offsets included, in
  // program units, as LinuxCNC gives them to a line that reads them (pkm home's programs do).
  for (int axis = 0; axis < kAxes; ++axis) parameters.set_numbered(5420 + axis, pos[axis]);
  try {
    read_block(line, parameters, block);
  } catch (const SyntaxError& error) {
    fail(error.column, error.message);
  }
  if (block.percent) {
    if (percent_program) {
      saw_end = true;
      ended = true;
      release_compensation(1);
      Block none;
      emit(CanonKind::program_end, none);
      return;
    }
    fail(1, "'%' only opens and closes a program");
  }
  if (block.block_delete && options.block_delete) return;
  if (block.o_word) {
    execute_o_word(block);
    return;
  }
  execute_block(block);
}

void Interpreter::State::apply_assignments(const Block& block) {
  for (const Assignment& a : block.assignments) {
    if (a.name.empty()) {
      parameters.set_numbered(a.number, a.value);
    } else if (Parameters::read_only(a.name)) {
      fail(a.column,
           "#<" + a.name + "> is read-only: a subroutine's endsub or return [value] sets it");
    } else {
      parameters.set_named(a.name, a.value);
    }
  }
}

void Interpreter::State::not_finite(const Canon& canon) const {
  // A move's column is its motion code's; other commands come from the line as a whole.
  const bool move = canon.kind == CanonKind::traverse || canon.kind == CanonKind::feed ||
                    canon.kind == CanonKind::arc || canon.kind == CanonKind::probe;
  throw GcodeError(file_name(), canon.line, move ? move_column : 0,
                   "calculation resulted in infinity or NaN (a number too large to use)");
}

Interpreter::Interpreter(std::filesystem::path program, InterpreterOptions options)
    : program_(std::move(program)), options_(std::move(options)) {}

Interpreter::~Interpreter() = default;

void Interpreter::run(const CanonSink& sink) {
  warnings_.clear();
  state_ = std::make_unique<State>(program_, options_, warnings_);
  state_->run(sink);
}

void Interpreter::start(const CanonSink& sink) {
  warnings_.clear();
  state_ = std::make_unique<State>(program_, options_, warnings_);
  state_->start(sink);
}

bool Interpreter::step() {
  return state_ && state_->step();
}

std::vector<std::filesystem::path> Interpreter::files_read() const {
  std::vector<std::filesystem::path> paths;
  if (!state_) return {program_};
  for (const auto& file : state_->files) paths.push_back(file->path);
  return paths;
}

}  // namespace pkm::gcode
