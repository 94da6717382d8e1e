#include "studies/engine/study_work.h"

#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "lib/study_file.h"
#include "studies/engine/study_loader.h"

namespace vrv {
namespace {

TEST(StudyWork, SumsItsPartsAndNamesTheLargest) {
  StudyWork work;
  EXPECT_EQ(work.largest(), nullptr);
  EXPECT_EQ(describe(work), "no field evaluations");
  work.add("truths", 256, 462);
  work.add("images at rate 8", 65536, 4.9e6);
  work.add("fan", 1, 10);
  EXPECT_EQ(work.evaluations(), 256 * 462 + 65536 * 4.9e6 + 10);
  ASSERT_NE(work.largest(), nullptr);
  EXPECT_EQ(work.largest()->what, "images at rate 8");
  EXPECT_EQ(describe(work), "about 3.2e+11 field evaluations (the largest part: images at rate 8, 65536 rays x 4.9e+06)");
  EXPECT_EQ(to_json(work)["parts"].size(), 3u);
}

LoadedStudy study_costing(double per_ray) {
  LoadedStudy s;
  s.source = "big.toml";
  s.work = [per_ray](bool quick) {
    StudyWork w;
    w.add("rays", quick ? 1 : 1000, per_ray);
    return w;
  };
  return s;
}

// Above the limit: one line naming the file, "(work)", the estimate and the limit that allows
// it; the variant counts; an estimate that is not a number is refused, never waved through.
TEST(StudyWork, TheLoaderRefusesWorkAboveTheLimit) {
  EXPECT_EQ(check_study_work(study_costing(1e6), false, 1e9).evaluations(), 1e9);
  EXPECT_NO_THROW(check_study_work(study_costing(1e7), true, 1e9));
  try {
    check_study_work(study_costing(1.01e7), false, 1e9);
    FAIL() << "not refused";
  } catch (const StudyFileError& e) {
    EXPECT_EQ(std::string(e.what()),
              "big.toml: (work): about 1e+10 field evaluations (the largest part: rays, 1000 rays x 1e+07), above "
              "the work limit of 1e+09; allow it with --max-work 1.1e+10");
  }
  EXPECT_THROW(check_study_work(study_costing(std::numeric_limits<double>::quiet_NaN()), false, 1e9),
               StudyFileError);
  // A configuration no plan can hold is the study file's problem, named as such.
  LoadedStudy unplannable = study_costing(1);
  unplannable.work = [](bool) -> StudyWork { throw std::invalid_argument("--step: gives more than 1e12 samples on one ray"); };
  try {
    check_study_work(unplannable, false, 1e9);
    FAIL() << "not refused";
  } catch (const StudyFileError& e) {
    EXPECT_EQ(std::string(e.what()), "big.toml: (work): --step: gives more than 1e12 samples on one ray");
  }
}

}  // namespace
}  // namespace vrv
