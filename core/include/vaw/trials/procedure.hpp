#pragma once
// The method's state machine: from a design and the answers so far, the next trial. No files and no
// clock: the same design and answers give the same trials, which is what resuming relies on.
#include <optional>
#include <vector>

#include "vaw/trials/trial.hpp"

namespace vaw::trials {

class Procedure {
 public:
  explicit Procedure(Design design);

  [[nodiscard]] const Design& design() const { return design_; }
  // The trial to run now; empty when the session is complete.
  [[nodiscard]] const std::optional<Trial>& next() const { return next_; }
  // Throws std::invalid_argument when the session is complete or the answer does not fit next() (a
  // judgement for a setting, a setting out of range, a negative time).
  void check(const Answer& a) const;
  // Answers next() after check(); on a throw nothing has changed.
  void answer(const Answer& a);

  [[nodiscard]] const std::vector<Record>& records() const { return records_; }
  // Trials in the whole session: exact except for staircases, whose length depends on the answers;
  // for them the most it can be.
  [[nodiscard]] int plannedTrials() const;
  // Staircase method: the scales at which each staircase reversed, in order.
  [[nodiscard]] const std::vector<std::vector<double>>& reversals() const { return reversals_; }

 private:
  struct StairState {
    double scale = 1.0;
    int trials = 0;
    int run = 0;        // > 0: consecutive "faster" answers; < 0: consecutive "slower" answers
    int direction = 0;  // last step: -1 down, +1 up, 0 none yet
  };

  void advance();
  [[nodiscard]] bool stairDone(std::size_t k) const;
  [[nodiscard]] Trial makeTrial(double scale) const;

  Design design_;
  std::vector<Record> records_;
  std::optional<Trial> next_;
  std::vector<double> order_;        // constant stimuli: every trial's scale, shuffled in blocks
  std::vector<StairState> stairs_;   // staircase method
  std::vector<int> round_;           // staircase method: the staircases still to ask in this round
  int roundIndex_ = 0;
  std::vector<std::vector<double>> reversals_;
  std::vector<double> posterior_;    // QUEST: log posterior on questGrid_
  std::vector<double> questGrid_;
};

}  // namespace vaw::trials
