// Where verify is along the job: a place that only moves forward. Each joint block's end is found
// by walking the job forward from the place the previous block ended, never by a search of the
// whole job, so a path that comes back over itself (closed contours, pen-up travel back along a
// drawn line, stacked passes) cannot pull the cursor to the wrong pass. Beside the cursor it keeps
// the place reached: how far the job is traced, which runs on beyond the block's end where the job
// stays within the tolerance of it (a job that turns back on itself there).
#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "pkm/verify/job_path.hpp"

namespace pkm::verify {

struct JobPlace {
  long piece = 0;  // index of the move in the job
  double u = 0.0;  // fraction of it
  bool before(const JobPlace& other) const {
    return piece < other.piece || (piece == other.piece && u < other.u);
  }
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
  // The reach is measured from the furthest place reached (see dwell_end), the search starts at
  // the cursor; it goes on at least to `inside_until_mm` (arc length along the job: inside_box).
  JobPlace find_end(const Eigen::Vector3d& point, double reach_mm, double slack_mm,
                    double inside_until_mm = 0.0);
  // The arc length along the job where it first leaves `box` beyond the place reached (an arc
  // that strays outside is taken to leave at its start). A
  // path that wiggles within the tolerance of a block is far longer than the block (a zigzag
  // across a line, 0.004 mm either side, 0.001 mm forward a move): no stretch of the job a
  // block traces leaves the box of its tool path grown by the tolerance.
  double inside_box_until_mm(const Eigen::AlignedBox3d& box);
  // How far beyond `end` the job stays within `radius_mm` of `point` (the block's end): a tool
  // standing at `point` is within the tolerance of all of it, so a path that turns back on itself
  // within the tolerance there (a job going back and forth by 1 um) is traced up to the returned
  // place. `end` itself where the job leaves the ball at once.
  JobPlace dwell_end(const JobPlace& end, const Eigen::Vector3d& point, double radius_mm);
  // The stretch from the cursor to `end` (moves without a controlled path left out; the cursor's
  // point alone when the stretch has no length), into `ranges`.
  void stretch_to(const JobPlace& end, std::vector<PieceRange>& ranges);
  // Moves the cursor to `end` (never back), where the next block's stretch starts, records
  // `reached` (at or beyond `end`, from dwell_end) as how far the job is traced, and lets the job
  // forget what lies behind the cursor.
  void advance(const JobPlace& end, const JobPlace& reached);

  const JobPlace& reached() const { return reached_; }
  // The point of the job at the place reached, as a stretch of no length, into `ranges`.
  void point_reached(std::vector<PieceRange>& ranges);

  double along_mm();          // arc length of the job up to the cursor
  double reached_along_mm();  // arc length of the job up to the place reached
  int line();                 // the job line of the move the cursor is in
  // After the last block: how much of the job lies beyond the cursor. Reads the rest of the job,
  // forgetting as it goes.
  struct Rest {
    double job_length_mm = 0.0;  // the whole job's controlled path
    double traced_mm = 0.0;      // up to the place reached
    int first_line = 0;  // the first move beyond the place reached with a path left to trace
  };
  Rest rest();

 private:
  struct Candidate {
    Nearest nearest;
    long piece = 0;
    bool at_start = false, at_end = false;
  };
  JobPath& path_;
  double along_mm(const JobPlace& place);
  JobPlace place_;
  JobPlace reached_;  // at or beyond place_
  std::vector<Candidate> candidates_;
};

}  // namespace pkm::verify
