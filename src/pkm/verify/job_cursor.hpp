// Where verify is along the job: a place that only moves forward. Each joint block's end is found
// by walking the job forward from the place the previous block ended, never by a search of the
// whole job, so a path that comes back over itself (closed contours, pen-up travel back along a
// drawn line, stacked passes) cannot pull the cursor to the wrong pass.
#pragma once

#include <vector>

#include "pkm/verify/job_path.hpp"

namespace pkm::verify {

struct JobPlace {
  long piece = 0;  // index of the move in the job
  double u = 0.0;  // fraction of it
};

// Part of one move, from fraction u0 to u1: a piece of the stretch a block must trace.
struct PieceRange {
  const JobPiece* piece = nullptr;
  double u0 = 0.0, u1 = 0.0;
};

class JobCursor {
 public:
  explicit JobCursor(JobPath& path) : path_(path) {}

  // Where a block ending at `point` (controlled coordinates) leaves the job: walking forward from
  // the cursor at most `reach_mm` along the job, the first place where the distance to `point`
  // has a local minimum within `slack_mm` of the smallest one. The cursor itself when no move
  // with a controlled path lies ahead.
  JobPlace find_end(const Eigen::Vector3d& point, double reach_mm, double slack_mm);
  // The stretch from the cursor to `end` (moves without a controlled path left out; the cursor's
  // point alone when the stretch has no length), into `ranges`.
  void stretch_to(const JobPlace& end, std::vector<PieceRange>& ranges);
  // Moves the cursor to `end` (never back) and lets the job forget what lies behind.
  void advance(const JobPlace& end);

  double along_mm();  // arc length of the job up to the cursor
  int line();         // the job line of the move the cursor is in
  // After the last block: how much of the job lies beyond the cursor. Reads the rest of the job,
  // forgetting as it goes.
  struct Rest {
    double job_length_mm = 0.0;  // the whole job's controlled path
    double traced_mm = 0.0;      // up to the cursor
    int first_line = 0;          // the first move beyond the cursor with a path left to trace
  };
  Rest rest();

 private:
  struct Candidate {
    Nearest nearest;
    long piece = 0;
    bool at_start = false, at_end = false;
  };
  JobPath& path_;
  JobPlace place_;
  std::vector<Candidate> candidates_;
};

}  // namespace pkm::verify
