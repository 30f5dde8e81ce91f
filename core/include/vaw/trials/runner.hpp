#pragma once
// Runs a design trial by trial against its results file: what the trials panel, the headset and
// `vaw-sim trials simulate` drive. Each answer is on disk (written whole, fsync'ed) before answer()
// returns and before next() moves on, so a crash or a kill loses no answered trial; opening the file
// again resumes at the first unanswered trial.
#include <filesystem>
#include <optional>
#include <vector>

#include "vaw/trials/procedure.hpp"
#include "vaw/trials/results.hpp"

namespace vaw::trials {

class Runner {
 public:
  // Creates `results` for `design`, or resumes it if it exists; an existing file must carry the same
  // design. A torn last record is cut off (recovered() says so) and its trial is asked again. Throws
  // vaw::InputError for a malformed file or another design, std::system_error when the file cannot be
  // created, locked or written (another session holds it, say).
  static Runner open(const Design& design, const std::filesystem::path& results);
  // Resumes from the results file alone, with the design its header carries.
  static Runner resume(const std::filesystem::path& results);

  Runner(Runner&& other) noexcept;
  Runner& operator=(Runner&& other) noexcept;
  Runner(const Runner&) = delete;
  Runner& operator=(const Runner&) = delete;
  ~Runner();

  [[nodiscard]] const Design& design() const { return procedure_.design(); }
  // The trial to run now (scenario, scale, blinded, ...); empty when the session is complete.
  [[nodiscard]] const std::optional<Trial>& next() const { return procedure_.next(); }
  // Records the answer to next(). Throws std::invalid_argument for an answer that does not fit the trial
  // and std::system_error when the disk refuses it; either way nothing is recorded and next() stays.
  void answer(const Answer& a);

  [[nodiscard]] const std::vector<Record>& records() const { return procedure_.records(); }
  [[nodiscard]] int answered() const { return static_cast<int>(procedure_.records().size()); }
  [[nodiscard]] int plannedTrials() const { return procedure_.plannedTrials(); }
  // The torn record that open() cut off, if there was one.
  [[nodiscard]] const std::optional<TornTail>& recovered() const { return recovered_; }
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  Runner(Procedure procedure, std::filesystem::path path, int fd, std::optional<TornTail> recovered);
  static Runner openExisting(const std::optional<Design>& design, const std::filesystem::path& results);

  Procedure procedure_;
  std::filesystem::path path_;
  int fd_ = -1;
  std::optional<TornTail> recovered_;
};

}  // namespace vaw::trials
