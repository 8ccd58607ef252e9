// Points in the apex of a needle: closed Polyline containers of the random search of
// PointsInNarrowCorners with a corner narrower than one degree (0.29 to 0.66), each played by the
// hybrid step and by the predictive one. Before the apex rules, a point left each of them in both modes
// through the tip:
//
// - A point sliding along one face into the apex met the other face's line past the joint, by the
//   round-off of the first over the sine of the apex (119 round-offs in an apex of half a degree),
//   further than a face reached past its end for so shallow an approach; the slide ended past the joint
//   and the point fell out of the tip. Now a face reaches that far past the joint of an apex, and a
//   slide ends beyond it (time_of_impact.cpp, slideEndTime).
// - Stopped in the apex, the point slid on along the face gravity pressed it into, past the joint, and
//   fell out. Now a body stopped in a corner whose faces hold it up sleeps there (squeezeAt).
// - Come to rest, or bounced off, a few round-offs past the joint (where the time of impact took it as
//   met at the face's end), the point was outside both faces and their fixture's box, and a throw from
//   the game sent it out. Now a point met at a face's end from beyond it is moved to that end
//   (placePointOnFace).
//
// The search's 300 containers of each of seeds 3 to 7, Polyline: these five were its only escapes.
#include <gtest/gtest.h>

#include <rattle/rattle.h>

#include <vector>

#include "container_search_support.h"

using namespace rattle;
using container_search::Container;
using container_search::Walls;

namespace {

const Container kNeedles[] = {
    // search seed 3, trial 95: an apex of 0.48 degrees
    {StepMode::Hybrid,
     Walls::Polyline,
     {{-0x1.6d2873d1b58b4p+3, -0x1.ad5881056e1bcp+3}, {0x1.7c37a35ca57a2p+2, -0x1.980223e281e92p+3}, {0x1.7d8141cd97e62p+2, -0x1.935278611bda5p+3}},
     {0x1.be20faf6cdd51p-2},
     {{{0x1.f72bc2b73b75ep-1, -0x1.9bad197634163p+3}, {-0x1.05d1a08aa6ceep+3, -0x1.412d21deb648cp+0}, 0x0p+0, 0x1.092c284c95c39p-1},
      {{-0x1.feddf1dd3c172p+0, -0x1.9f966d8a5724fp+3}, {-0x1.1e237294c47b9p+1, 0x1.d3fd48468fb71p+3}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.1914ad1daa272p+2, -0x1.97bbbabdfc976p+3}, {0x1.d146c5e0e7148p+0, 0x1.63871f5bd6cfdp+0}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.b67708ee03d97p+0, -0x1.9ba6465507e3p+3}, {0x1.5f4ebff405ffp+2, -0x1.1fd61beef85bdp+3}, 0x0p+0, 0x1.7a585526bbd98p-1},
      {{-0x1.126d0bae8ae77p+1, -0x1.a035c155ff97ap+3}, {-0x1.1eb0da153c178p+2, 0x1.b5d365daf1205p+3}, 0x0p+0, 0x1.5c124a26c134cp-5},
      {{0x1.41fa2a56c501p+0, -0x1.9cc4516ead6cp+3}, {-0x1.d7b6b83f5ce75p+2, -0x1.b9db435ee6e6bp+2}, 0x0p+0, 0x1.7116204625086p-2},
      {{-0x1.9c592856902acp+0, -0x1.9f022358a8e83p+3}, {0x1.e6d0b7acece23p+2, -0x1.744dc164107f6p+3}, 0x0p+0, 0x1.1b13bc59a9232p-1},
      {{0x1.4b1144b642211p+0, -0x1.9d5806c85fc99p+3}, {0x1.0af7bb49d6436p-1, 0x1.ad4adb624b474p-3}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.78c30a8bf611dp+1, -0x1.99ba63decd7b8p+3}, {-0x1.4bc6a61c4e8ddp+3, -0x1.bf19b4e5cf293p+1}, 0x0p+0, 0x1.fbad54b7f8a8dp-2},
      {{0x1.40fffafbf8735p+0, -0x1.9da4e564a8618p+3}, {0x1.1ce23705a0692p-3, 0x1.b512ea9681a37p-2}, 0x0p+0, 0x1.cb5d838de46ccp-2},
      {{-0x1.c7c8546a1d6a2p+1, -0x1.a1bea3883a482p+3}, {-0x1.1ac8b94740e63p-1, -0x1.a87cef91b40a1p-1}, 0x0p+0, 0x1.854293a11dc89p-1},
      {{-0x1.9f8073f60b267p+0, -0x1.9f507e91ac8d8p+3}, {0x1.676a540ee76edp-2, 0x1.7daaac5d1c3c9p-2}, 0x0p+0, 0x1.68b804b430a49p-1}},
     {{0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
    // search seed 4, trial 227: an apex of 0.66 degrees
    {StepMode::Hybrid,
     Walls::Polyline,
     {{0x1.2f60237dfb0cep+4, 0x1.c02123feb7d42p+3}, {0x1.4a35712fd4cf9p+4, 0x1.cc0f7f7d88d93p+3}, {0x1.4b1087979ceeep+4, 0x1.cd1b996aec54bp+3}},
     {0x1.7d3debb9b1f04p-1},
     {{{0x1.44476b9f334cap+4, 0x1.c9a2861267b8bp+3}, {0x1.65e02900f05ebp-1, -0x1.3b760946e9688p+3}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.47f96846aa729p+4, 0x1.cb2f1e67ff151p+3}, {-0x1.beeb7fea3e88dp+1, -0x1.892eaef4914b3p+1}, 0x0p+0, 0x1.9dcdc3e01ef93p-2},
      {{0x1.4495854a1ba9ap+4, 0x1.c9c4afdeceb0ap+3}, {-0x1.1c9c8dc15113p+2, 0x1.7bf2c865c3817p+3}, 0x0p+0, 0x1.e725cde1676d7p-2},
      {{0x1.493e432bae039p+4, 0x1.cbe9a73acef43p+3}, {-0x1.599cc17711c4fp+2, 0x1.29ce27effee44p+2}, 0x0p+0, 0x1.1c2852f513bf6p-1},
      {{0x1.3e771550bb9b9p+4, 0x1.c6e6ee92f980bp+3}, {-0x1.07564a288d7fep+1, -0x1.a8ab855e8b941p+3}, 0x0p+0, 0x1.85aa070f9e832p-1},
      {{0x1.4a9b794945598p+4, 0x1.ccad5e950bd19p+3}, {-0x1.16aad84131aeap+0, 0x1.0c62762d8b02ep+2}, 0x0p+0, 0x1.6a16378a20b52p-2},
      {{0x1.455ed01229f8ap+4, 0x1.ca47404952949p+3}, {0x1.6a2de7251fb74p+3, 0x1.d19cae38f46d4p+1}, 0x0p+0, 0x1.78ddcbcd23d5cp-2},
      {{0x1.4157969dc0c31p+4, 0x1.c82ddf40dee0cp+3}, {-0x1.169a8d80dcfb3p+3, 0x1.5c9b24f75c9bcp+3}, 0x0p+0, 0x1.a0dd953b3befp-2},
      {{0x1.4285b94a6467cp+4, 0x1.c8dabee21eaaep+3}, {0x1.d2fb73fcbd688p+0, -0x1.94905d82e63acp+2}, 0x0p+0, 0x1.33ff33107f361p-1},
      {{0x1.4211be660fed2p+4, 0x1.c8a27617f585p+3}, {0x1.9b551966a513bp+0, 0x1.312e1b3e67af1p+2}, 0x0p+0, 0x1.19799812dea11p-40}},
     {{0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
    // search seed 6, trial 33: an apex of 0.46 degrees
    {StepMode::Hybrid,
     Walls::Polyline,
     {{-0x1.73ce01f8f8bap+4, 0x1.9bf53ba48cc18p-1}, {-0x1.6941fc9e60d88p+4, 0x1.6bb3dd55ce75cp+0}, {-0x1.687057c79f294p+4, 0x1.7ab9fb63b384ap+0}},
     {0x1.b009b3718a157p-4},
     {{{-0x1.69ceb8bf5ce02p+4, 0x1.657db6b3d468fp+0}, {0x1.91896c6a77501p+1, -0x1.5008afddcb0bfp+2}, 0x0p+0, 0x1.8f4b03b19805ep-1},
      {{-0x1.6c7c20569cbf5p+4, 0x1.3c641cf2c679dp+0}, {0x1.1fdcb4187539bp+1, -0x1.a0ba98101dfefp-5}, 0x0p+0, 0x1.f62b8f25a7279p-3},
      {{-0x1.6d08df6606861p+4, 0x1.33eb97fe9a12dp+0}, {-0x1.093a1cf277793p+2, -0x1.4dbba2609ef5bp+2}, 0x0p+0, 0x1.56df45305c0dp-5},
      {{-0x1.6cd33dcb09c4fp+4, 0x1.37139aadb77b5p+0}, {0x1.be1ea499536cdp-1, 0x1.b903662747603p+0}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.6d13fdfe8b254p+4, 0x1.33a819f370fddp+0}, {-0x1.26e1a0470ac52p+2, 0x1.2859f8a2119c9p+1}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.696ccb0bf5135p+4, 0x1.6a7049f7cb75ap+0}, {0x1.300db53403be3p+2, -0x1.ee37aae3e4bffp+2}, 0x0p+0, 0x1.b4a36d65523b4p-1},
      {{-0x1.69c04ee6a507fp+4, 0x1.6552f4e9705cfp+0}, {0x1.7ef43552b0a04p+3, -0x1.9787f7f89317ep+1}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.6ee13ddd0b3e5p+4, 0x1.1810782aa8b15p+0}, {0x1.807fd71531f0bp+2, -0x1.d6912b317044fp+2}, 0x0p+0, 0x1.4bbf68857250bp-4},
      {{-0x1.6bba035bd646cp+4, 0x1.48267f6220d36p+0}, {-0x1.8d6ad1abaa736p+3, 0x1.f1fbccd67b4cfp-5}, 0x0p+0, 0x1.a3906d3ce42d6p-2},
      {{-0x1.6d8c6bfa838p+4, 0x1.2cda65b406b91p+0}, {0x1.64d7592f8381bp+2, -0x1.b5f60411cd99bp+1}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.6d59cf62e382ap+4, 0x1.2ee6d6fbff91ep+0}, {-0x1.eb7fdde289cd6p+2, 0x1.44bad593bfdcap+1}, 0x0p+0, 0x1.19799812dea11p-40}},
     {{0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
    // search seed 6, trial 86: an apex of 0.29 degrees
    {StepMode::Hybrid,
     Walls::Polyline,
     {{-0x1.df0f6a8ab426ap+3, 0x1.f2013d87c6238p+2}, {-0x1.e00ff027bb682p+3, 0x1.efba415f103ffp+2}, {-0x1.eab8ef179b0c2p+3, 0x1.d4245f1c6c494p+2}},
     {0x1.59c343bc305f8p-2},
     {{{-0x1.e1a2e3594ed12p+3, 0x1.eb83f82608625p+2}, {-0x1.fa7998fc4ec83p+2, -0x1.70281ff009ee3p+3}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.e376ed7767318p+3, 0x1.e6c95c5315894p+2}, {0x1.38f1a065f787cp+3, -0x1.5e70f01a71377p+2}, 0x0p+0, 0x1.7f13781382f65p-2},
      {{-0x1.e80c5a4014523p+3, 0x1.dafebd66d8356p+2}, {-0x1.9bfece6ac8024p+2, -0x1.97bc4769563bdp+3}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.dfc79079f4acap+3, 0x1.f0444d9f49e45p+2}, {0x1.3178bd950913ep+3, -0x1.0adea3c8c7aaep+3}, 0x0p+0, 0x1.8da47ae25165cp-2},
      {{-0x1.e2dc882c14009p+3, 0x1.e85ae6e80d2a1p+2}, {0x1.5d823e5937f6ep-3, 0x1.dd5cba57e4ceap-2}, 0x0p+0, 0x1.1aff9914dec46p-3},
      {{-0x1.e300f4eecccaap+3, 0x1.e80447d483abap+2}, {-0x1.3357d828272fp+1, 0x1.1eea7220575fep+0}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.e08fa457fe845p+3, 0x1.ee55d88e3207fp+2}, {-0x1.a8315c5fa951ap+3, -0x1.c461df949bc9fp-1}, 0x0p+0, 0x1.1d8d66dbc358fp-3},
      {{-0x1.e62a3c3b0f8d2p+3, 0x1.dfdfd7a7dd405p+2}, {0x1.2dbd468d95771p+0, -0x1.dfad8f073489fp-1}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.e29e01a69f1ddp+3, 0x1.e900d2905c60fp+2}, {0x1.071b840e50f0dp-3, -0x1.265cc05397b15p-1}, 0x0p+0, 0x1.13a52d07ba70fp-3},
      {{-0x1.e24e6fb8eab37p+3, 0x1.e9c59bcbc68a7p+2}, {0x1.442f494833eaap+1, 0x1.ced45a909d8bp+2}, 0x0p+0, 0x1.9715a67fc21cfp-1},
      {{-0x1.e4558eb4c4601p+3, 0x1.e48da83763394p+2}, {0x1.84225c61cbd6cp+3, -0x1.2c288a6534086p+2}, 0x0p+0, 0x1.944bb0e7ea70dp-1},
      {{-0x1.e1bf3695c4311p+3, 0x1.eb386625df0dcp+2}, {0x1.3c945d23aa655p+1, 0x1.f23c714905a4dp+2}, 0x0p+0, 0x1.c57d32f473f78p-1},
      {{-0x1.e276ab323e00ep+3, 0x1.e968b6f8ae28fp+2}, {0x1.2ed076d676f08p+0, -0x1.2aded647d230ep-1}, 0x0p+0, 0x1.19799812dea11p-40}},
     {{0x1.999999999999ap-4, 0, {0x1.b815b100855d6p+2, -0x1.36aa597d03da3p-5}}},
     0x0p+0},
    // search seed 6, trial 144: an apex of 0.62 degrees
    {StepMode::Hybrid,
     Walls::Polyline,
     {{0x1.abd6d8a83e48fp+3, -0x1.90659afbdabdbp+1}, {0x1.a9e26889717e9p+3, -0x1.8db35301ff5edp+1}, {0x1.2cb57298d228ap+3, -0x1.8c6bfc8624372p+2}},
     {0x1.f5655cab5f4abp-2},
     {{{0x1.53b45a8b9aa29p+3, -0x1.4ee4830f04779p+2}, {-0x1.f9c1de5b66e06p-4, -0x1.b2e2726e89838p-2}, 0x0p+0, 0x1.54f0abd6b9959p-2},
      {{0x1.82c820ced2c7cp+3, -0x1.04a711cf91de1p+2}, {-0x1.fd4fd2ac09c6dp-1, -0x1.4a9a620145157p+0}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.81214c84c5d5dp+3, -0x1.08e981f0781dbp+2}, {0x1.5043e6d621f6fp+3, -0x1.2f4b5b2c48cbcp+1}, 0x0p+0, 0x1.a345908a87147p-1},
      {{0x1.a3d645a074c4fp+3, -0x1.a81d1c01aa13p+1}, {-0x1.09f49d22c2b7fp+3, 0x1.2a1f80ddce466p+3}, 0x0p+0, 0x1.261947633c52bp-3},
      {{0x1.a70127bff8219p+3, -0x1.9b3daefc9f619p+1}, {0x1.ebd2854b456f8p+1, -0x1.3b21af08323f7p+1}, 0x0p+0, 0x1.0430db5aa04ap-2},
      {{0x1.6a8c84158fa47p+3, -0x1.2c2f48e255363p+2}, {0x1.4ee10ddcc2741p-1, 0x1.9d3cab6285bbdp+1}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.79b366d6585cdp+3, -0x1.148d4f93a2455p+2}, {0x1.2381bf037cac4p+3, -0x1.557bdedb808fbp+2}, 0x0p+0, 0x1.19799812dea11p-40}},
     {{0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
};

}  // namespace

TEST(PointsInNeedleApices, NoPointLeavesThroughTheTipInEitherMode) {
  std::vector<Container> containers;
  for (const Container& c : kNeedles) {
    for (StepMode mode : {StepMode::Hybrid, StepMode::Predictive}) {
      containers.push_back(c);
      containers.back().mode = mode;
    }
  }
  container_search::playEachChecked(containers.data(), containers.size());
}

// A joint that turns up by a twentieth of a degree has as small a sine as a needle's apex, but a point
// sliding along the floor into it is not in a wedge: it goes on up the next face, neither stopped at the
// joint nor moved back to it, and never below the floor.
TEST(PointsInNeedleApices, APointSlidesOnOverANearlyStraightRisingJoint) {
  for (StepMode mode : {StepMode::Hybrid, StepMode::Predictive}) {
    SCOPED_TRACE(mode == StepMode::Hybrid ? "hybrid" : "predictive");
    World w(container_search::searchWorld(mode));
    const BodyId ground = w.createBody({.type = BodyType::Static});
    const Vec2 joint{10, 0}, far{30, 0.0175};  // 20 units rising 0.0175: 0.05 degrees
    w.createFixture(ground, {.geometry = Polyline{{{0, 0}, joint, far}}});
    const BodyId point = w.createBody({.type = BodyType::Dynamic, .position = {1, 0}, .velocity = {4, 0}});
    w.createFixture(point, {.geometry = Circle{{0, 0}, 0}});
    double lastX = 1;
    for (int s = 0; s < 240; ++s) {
      w.step(1.0 / 60);
      ASSERT_FALSE(w.stats().eventBudgetReached) << "step " << s;
      const Vec2 p = w.position(point);
      // Above the floor: the line of the face beneath it, within round-off.
      const double floorY = p.x <= joint.x ? 0.0 : (p.x - joint.x) * (far.y - joint.y) / (far.x - joint.x);
      ASSERT_GE(p.y - floorY, -1e-12) << "step " << s << ", x " << p.x;
      ASSERT_GE(p.x, lastX) << "step " << s;  // on, never back
      lastX = p.x;
    }
    // Four seconds at 4 units/s, slowed a little on the rise by gravity's part along it: past the joint.
    EXPECT_GT(w.position(point).x, 16.0);
  }
}
