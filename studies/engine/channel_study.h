#pragma once
// A study of an RGB scene: its kind's study of each channel in turn.  The channels share one
// extinction, so channel c of an RGB image is the grey image of the scene with channel c's transfer
// function and background (lib/scene.h channel_scene): bit for bit for a discrete cast, and the
// reference of each channel is its grey reference.  Each channel's tables, images and plots go to
// DIR/red, DIR/green and DIR/blue; its checks are the study's, named "red: ...", and its work is
// counted once per channel.
#include <functional>
#include <string>
#include <string_view>

#include "studies/engine/study_driver.h"

namespace vrv {

// The kind's plan for channel c (0, 1, 2) of the study's RGB scene, its study named
// channel_study_name(name, c) (which its LaTeX labels carry, so that the channels' differ).
using ChannelPlan = std::function<StudyPlan(int channel)>;

// "red", "green", "blue".
std::string_view channel_name(int channel);
// "NAME-red" and so on.
std::string channel_study_name(std::string_view study, int channel);

// One plan that runs plan_channel(0), (1), (2) in turn, each made when its turn comes (so one
// channel's grids are held at a time).  `red`: the red channel's plan, already made, whose work
// estimates (full and --quick, taken now; it is then released) stand for each channel's (they do
// not depend on the transfer function).  Channels 1 and 2 are planned once now and released, so
// that a file error of theirs comes before anything runs.
StudyPlan per_channel_plan(StudyPlan red, ChannelPlan plan_channel);

}  // namespace vrv
