#include "pkm/certify/job_check.hpp"

#include "pkm/verify/job_path.hpp"

namespace pkm::certify {

JobCheck check_job(const machine::Machine& machine, const std::filesystem::path& job,
                   const JobCheckOptions& options) {
  JobCheck check;
  check.file = job.string();
  const MoveProver prover(machine, options.proof);
  check.unavailable = prover.unavailable();
  verify::JobPath path(machine, job, options.job_options, options.origin);
  for (long index = 0;; ++index) {
    const verify::JobPiece* piece = path.piece(index);
    if (piece == nullptr) break;
    path.forget_before(index);
    if (options.on_line) options.on_line(piece->line());
    const MoveProof proof = prover.prove(piece->segment);
    ++check.moves;
    check.pieces += proof.pieces;
    switch (proof.verdict) {
      case Verdict::proven:
        ++check.proven;
        continue;
      case Verdict::violated:
        ++check.violated;
        break;
      case Verdict::undecided:
        ++check.undecided;
        break;
    }
    if (!check.first_failure) {
      check.first_failure = FailedMove{index, piece->line(), proof.verdict, *proof.finding};
    }
  }
  if (const auto warning = path.pen_warning()) check.warnings.push_back(*warning);
  return check;
}

}  // namespace pkm::certify
