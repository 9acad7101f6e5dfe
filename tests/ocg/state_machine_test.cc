#include <gtest/gtest.h>

#include "ocg/core/file_io.h"
#include "ocg/ocg/judgement_terms.h"
#include "ocg/ocg/replay_format.h"
#include "ocg/ocg/state_machine.h"
#include "test_support.h"

namespace ocg {
namespace {

using S = ObjectState;

TEST(Equation1, ActiveEdgeRate) {
  EXPECT_DOUBLE_EQ(ActiveEdgeRate(0, 0), 0.0);  // no neighbours: treated as 0
  EXPECT_DOUBLE_EQ(ActiveEdgeRate(0, 7), 0.0);
  EXPECT_DOUBLE_EQ(ActiveEdgeRate(3, 12), 0.25);
  EXPECT_DOUBLE_EQ(ActiveEdgeRate(12, 12), 1.0);
}

TEST(Equation2, IncrementBandsAndBoundaries) {
  const OcgOptions options;
  EXPECT_EQ(DoubtIncrement(1.0, true, options), 30.0);
  EXPECT_EQ(DoubtIncrement(0.999, true, options), 20.0);
  EXPECT_EQ(DoubtIncrement(0.5, true, options), 20.0);  // [0.5, 1)
  EXPECT_EQ(DoubtIncrement(0.4999, true, options), 10.0);
  EXPECT_EQ(DoubtIncrement(0.2001, true, options), 10.0);
  EXPECT_EQ(DoubtIncrement(0.2, true, options), 0.0);  // (tau, 0.5) is open at tau
  EXPECT_EQ(DoubtIncrement(0.1, true, options), 0.0);
  for (double rate : {0.0, 0.2, 0.3, 0.5, 1.0})
    EXPECT_EQ(DoubtIncrement(rate, false, options), 0.0);
}

TEST(StateMachine, ObservedResetsFromAnyLiveState) {
  const OcgOptions options;
  for (S state : {S::kObserved, S::kRecentlyObserved, S::kUnknown, S::kSuspicious}) {
    const StateAndDoubt next = NextState({state, 45.0}, true, 0.0, 30.0, options);
    EXPECT_EQ(next.state, S::kObserved);
    EXPECT_EQ(next.doubt, 0.0);
  }
}

TEST(StateMachine, RecentStatesAtAndAroundTau) {
  const OcgOptions options;
  for (S state : {S::kObserved, S::kRecentlyObserved}) {
    EXPECT_EQ(NextState({state, 0}, false, 0.19, 0, options).state, S::kUnknown);
    EXPECT_EQ(NextState({state, 0}, false, 0.2, 0, options).state, S::kRecentlyObserved);
    EXPECT_EQ(NextState({state, 0}, false, 0.9, 0, options).state, S::kRecentlyObserved);
  }
}

TEST(StateMachine, UnknownEntersSuspiciousOnlyAboveTau) {
  const OcgOptions options;
  EXPECT_EQ(NextState({S::kUnknown, 0}, false, 0.2, 0, options).state, S::kUnknown);
  const StateAndDoubt entered = NextState({S::kUnknown, 0}, false, 0.6, 20, options);
  EXPECT_EQ(entered.state, S::kSuspicious);
  EXPECT_EQ(entered.doubt, 20.0);  // d = inc(r, P), not accumulated
}

TEST(StateMachine, SuspiciousAccumulatesThenDecidesOnLeaving) {
  const OcgOptions options;
  EXPECT_EQ(NextState({S::kSuspicious, 30}, false, 1.0, 30, options).doubt, 60.0);
  // At exactly tau the camera has not left: keep accumulating (increment 0 there).
  const StateAndDoubt at_tau = NextState({S::kSuspicious, 30}, false, 0.2, 0, options);
  EXPECT_EQ(at_tau.state, S::kSuspicious);
  EXPECT_EQ(at_tau.doubt, 30.0);
  const StateAndDoubt outlier = NextState({S::kSuspicious, 60}, false, 0.1, 0, options);
  EXPECT_EQ(outlier.state, S::kOutlier);
  const StateAndDoubt exactly = NextState({S::kSuspicious, 50}, false, 0.1, 0, options);
  EXPECT_EQ(exactly.state, S::kUnknown) << "d must exceed tau_doubt, not equal it";
  EXPECT_EQ(exactly.doubt, 0.0);
}

TEST(StateMachine, ThresholdsAreConfigurable) {
  OcgOptions options;
  options.tau_observable = 0.4;
  options.tau_doubt = 100;
  EXPECT_EQ(NextState({S::kObserved, 0}, false, 0.3, 0, options).state, S::kUnknown);
  EXPECT_EQ(NextState({S::kSuspicious, 90}, false, 0.3, 0, options).state, S::kUnknown);
  EXPECT_EQ(DoubtIncrement(0.45, true, options), 10.0);
  EXPECT_EQ(DoubtIncrement(0.35, true, options), 0.0);
}

TEST(Options, ModesParseAndReject) {
  OcgOptions options;
  EXPECT_EQ(options.mode, "improved") << "the default mode (issue 18)";
  options.mode = "paper";
  const OcgModes paper = options.modes();
  EXPECT_FALSE(paper.isolated_fallback || paper.box_in_image || paper.dropout_guard ||
               paper.dropout_discount);
  options.mode = "dropout";
  EXPECT_TRUE(options.modes().dropout_discount && !options.modes().detected_view);
  options.mode = "fallback+guard";
  EXPECT_NO_THROW(options.Check());
  EXPECT_TRUE(options.modes().isolated_fallback);
  EXPECT_FALSE(options.modes().box_in_image);
  EXPECT_TRUE(options.modes().dropout_guard);
  options.mode = "improved";
  const OcgModes all = options.modes();
  EXPECT_TRUE(all.isolated_fallback && all.box_in_image && all.dropout_guard && all.detected_view &&
              all.restore && all.dropout_discount && all.point_presence);
  EXPECT_FALSE(all.detection_reliability) << "measured, not adopted (docs/ocg.md)";
  options.mode = "improved+reliability";
  EXPECT_TRUE(options.modes().detection_reliability && options.modes().detected_view);
  options.mode = "paper+guard";
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options.mode = "fallbak";
  EXPECT_THROW(options.Check(), std::invalid_argument);
  EXPECT_EQ(paper.strategy, ChangeStrategy::kGraph);
  options.mode = "off";
  EXPECT_EQ(options.modes().strategy, ChangeStrategy::kOff);
  options.mode = "visibility";
  EXPECT_EQ(options.modes().strategy, ChangeStrategy::kVisibility);
  options.mode = "visibility+guard";
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options.mode = "visibility";
  options.visibility_keyframes = 0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

// The mode names are the judgement terms' list: each name alone switches its own term and
// nothing else, "improved" the terms marked for it, and the unknown-mode message lists all.
TEST(Options, ModesAreTheListedJudgementTerms) {
  const std::vector<JudgementTerm>& terms = JudgementTerms();
  ASSERT_LE(terms.size(), kMaxJudgementTerms);
  std::uint32_t improved = 0;
  for (std::size_t i = 0; i < terms.size(); ++i) {
    const OcgModes alone = ParseOcgMode(terms[i].name);
    EXPECT_EQ(alone.terms, 1u << i) << terms[i].name;
    if (terms[i].flag) {
      EXPECT_TRUE(alone.*terms[i].flag) << terms[i].name;
    }
    for (std::size_t j = 0; j < terms.size(); ++j) {
      if (j != i && terms[j].flag) {
        EXPECT_FALSE(alone.*terms[j].flag) << terms[i].name;
      }
    }
    if (terms[i].in_improved) improved |= 1u << i;
  }
  EXPECT_EQ(ParseOcgMode("improved").terms, improved);
  EXPECT_EQ(ParseOcgMode("paper").terms, 0u);
  EXPECT_EQ(ParseOcgMode("off").terms, 0u);
  try {
    ParseOcgMode("nonsense");
    ADD_FAILURE() << "an unknown mode must throw";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find(JudgementTermNames()), std::string::npos)
        << error.what();
  }
}

// The docs are made from the lists: docs/ocg.md holds the modes table and the observation
// fields table as the code prints them, so a term or field added to its list and not to
// the docs fails here (tools/settings_docs.py writes them).
TEST(JudgementTerms, DocsTablesAreTheRegistries) {
  const std::string docs = ReadTextFile(testing::SourceDir() + "/docs/ocg.md");
  const std::string modes = JudgementTermsMarkdown();
  for (const JudgementTerm& term : JudgementTerms()) {
    EXPECT_NE(modes.find(std::string("| `") + term.name + "` |"), std::string::npos) << term.name;
  }
  EXPECT_NE(docs.find(modes), std::string::npos)
      << "docs/ocg.md: the modes table is not the judgement terms' list; run "
         "tools/settings_docs.py build/tools/ocg_slam";
  const std::string fields = ObservationFieldsMarkdown();
  const KeyframeObservation observation;
  VisitObservationFields(
      [&fields](const ObservationField& field, const auto&) {
        EXPECT_NE(fields.find(std::string("| `") + field.name + "` |"), std::string::npos)
            << field.name;
      },
      observation);
  EXPECT_NE(docs.find(fields), std::string::npos)
      << "docs/ocg.md: the observation fields table is not the field list; run "
         "tools/settings_docs.py build/tools/ocg_slam";
}

}  // namespace
}  // namespace ocg
