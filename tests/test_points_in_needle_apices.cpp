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
//
// The same needles of separate Segments, one fixture a side (with other throws): the faces met at their
// joints as unrelated faces, each reaching past its end by its own round-off only where the approach was
// steeper than 1/64, and a point left each of them through the tip. Now a Segment's one neighbour at an
// end of it on the same body is read as a Polyline's (segment_neighbours.cpp). These six were the
// search's only escapes through Segments over the same seeds.
#include <gtest/gtest.h>

#include <rattle/rattle.h>

#include <span>
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

const Container kNeedlesOfSegments[] = {
    // search seed 3, trial 95: an apex of 0.48 degrees
    {StepMode::Hybrid,
     Walls::Segments,
     {{-0x1.6d2873d1b58b4p+3, -0x1.ad5881056e1bcp+3}, {0x1.7c37a35ca57a2p+2, -0x1.980223e281e92p+3}, {0x1.7d8141cd97e62p+2, -0x1.935278611bda5p+3}},
     {0x1.be20faf6cdd51p-2, 0x1.526947d81afb6p-2, 0x1.37a4f5cc4d98ep-2},
     {{{0x1.a1e1f8fd5a691p-5, -0x1.9dc071bcd7d11p+3}, {0x1.1a8c283bd6907p+2, -0x1.f1deaebc654e6p-1}, 0x0p+0, 0x1.06fe090874603p-3},
      {{-0x1.a8cb21e46461cp-1, -0x1.9fb740e6b695dp+3}, {0x1.0e872b0b37ee7p+0, 0x1.52237bd7d1462p+0}, 0x0p+0, 0x1.60f70da6337ccp-1},
      {{0x1.448e7d2ede0d4p+0, -0x1.9b356161556f8p+3}, {-0x1.eb5978346069dp-1, -0x1.465941c5a1e18p-3}, 0x0p+0, 0x1.aca628dfdafep-1},
      {{0x1.5c1e0010d3afcp+0, -0x1.9bba8f68e3ad2p+3}, {-0x1.e2bd82ef04a0ep+2, 0x1.923d658f53f15p+3}, 0x0p+0, 0x1.457a6bb183da7p-1},
      {{-0x1.32319a97c27b5p+2, -0x1.a3988b3286088p+3}, {-0x1.d6db0da85e6cp+1, 0x1.4a95ad2772774p+3}, 0x0p+0, 0x1.e916470a993d9p-1},
      {{0x1.eb39db51f5b22p+0, -0x1.9b996104f26bfp+3}, {0x1.efedfedd582abp+2, 0x1.d2bc32cf7ca57p+2}, 0x0p+0, 0x1.0887ac375510bp-1}},
     {{0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, 4, {-0x1.1be8cd5a70893p-1, 0x1.0f436425cbeb7p+2}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, 3, {-0x1.8d1c4450a1b54p+1, 0x1.dafbf64bb35a9p+1}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
    // search seed 3, trial 119: an apex of 0.60 degrees
    {StepMode::Hybrid,
     Walls::Segments,
     {{-0x1.a75e5f396563p-2, 0x1.5052d6797aaacp+4}, {-0x1.e72832b1c4adp+2, 0x1.5ab012c26208cp+4}, {-0x1.ee83f1b64cd56p+2, 0x1.59a0e8820e55ep+4}},
     {0x1.f68e98fd62824p-1, 0x1.654d24af000cbp-3, 0x1.8bef985373dd4p-1},
     {{{-0x1.4aab44e929f6ap+2, 0x1.56bddd0c5c461p+4}, {-0x1.5b0a13ad7f575p+2, -0x1.89f753ac1a975p+0}, 0x0p+0, 0x1.57d047d7b9b77p-1},
      {{-0x1.77628235842dbp+2, 0x1.57de5574630a3p+4}, {0x1.b3f7a5a8014cbp+2, 0x1.091401cbbc5fp+3}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.cacd53da5ad4dp+1, 0x1.54d37c3d12b64p+4}, {-0x1.2edb40eda7d99p+0, -0x1.25167bd79d9b7p+1}, 0x0p+0, 0x1.80b07f16d9734p-1},
      {{-0x1.981489d4c9a8ap+2, 0x1.5885951dd3b77p+4}, {0x1.5a8c988c68be3p+3, -0x1.76a7a56d513e8p+2}, 0x0p+0, 0x1.82d0c0739e737p-1}},
     {{0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
    // search seed 4, trial 227: an apex of 0.66 degrees
    {StepMode::Hybrid,
     Walls::Segments,
     {{0x1.2f60237dfb0cep+4, 0x1.c02123feb7d42p+3}, {0x1.4a35712fd4cf9p+4, 0x1.cc0f7f7d88d93p+3}, {0x1.4b1087979ceeep+4, 0x1.cd1b996aec54bp+3}},
     {0x1.7d3debb9b1f04p-1, 0x1.49b2909c99caap-1, 0x1.d768ec5777ec1p-2},
     {{{0x1.42474821d99cap+4, 0x1.c8c82edbe8a5fp+3}, {0x1.068e2e3ad4c2ap+3, 0x1.faec4461b63e8p+1}, 0x0p+0, 0x1.2b07621ed285ap-3},
      {{0x1.459662cba3f7bp+4, 0x1.ca4d3f9d702ebp+3}, {0x1.d596764416f9ap+1, -0x1.d485f50ade87ep+0}, 0x0p+0, 0x1.9a50f0b7375c7p-1},
      {{0x1.41d62310797d2p+4, 0x1.c8758737c45bcp+3}, {-0x1.a3f275c4e857p+3, 0x1.15003722c9927p+2}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.3fbad76dd8dbbp+4, 0x1.c796b98afdcb1p+3}, {-0x1.9be7abdf983c2p+0, -0x1.64c47df523984p+2}, 0x0p+0, 0x1.1c2852f513bf6p-1},
      {{0x1.3e771550bb9b9p+4, 0x1.c6e6ee92f980bp+3}, {-0x1.07564a288d7fep+1, -0x1.a8ab855e8b941p+3}, 0x0p+0, 0x1.85aa070f9e832p-1},
      {{0x1.4a9b794945598p+4, 0x1.ccad5e950bd19p+3}, {-0x1.16aad84131aeap+0, 0x1.0c62762d8b02ep+2}, 0x0p+0, 0x1.6a16378a20b52p-2},
      {{0x1.455ed01229f8ap+4, 0x1.ca47404952949p+3}, {0x1.6a2de7251fb74p+3, 0x1.d19cae38f46d4p+1}, 0x0p+0, 0x1.78ddcbcd23d5cp-2},
      {{0x1.4157969dc0c31p+4, 0x1.c82ddf40dee0cp+3}, {-0x1.169a8d80dcfb3p+3, 0x1.5c9b24f75c9bcp+3}, 0x0p+0, 0x1.a0dd953b3befp-2},
      {{0x1.4285b94a6467cp+4, 0x1.c8dabee21eaaep+3}, {0x1.d2fb73fcbd688p+0, -0x1.94905d82e63acp+2}, 0x0p+0, 0x1.33ff33107f361p-1},
      {{0x1.4211be660fed2p+4, 0x1.c8a27617f585p+3}, {0x1.9b551966a513bp+0, 0x1.312e1b3e67af1p+2}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.3e7af8d443cccp+4, 0x1.c72bb7f5ff1bfp+3}, {-0x1.1396d8fd99a88p+1, 0x1.d4c7a4b0e4fd1p+1}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.43ae41ffbf39bp+4, 0x1.c93ff63aadb02p+3}, {-0x1.5c296b84f15d5p+3, -0x1.482467fea9463p+3}, 0x0p+0, 0x1.a514615c7a594p-4}},
     {{0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
    // search seed 6, trial 33: an apex of 0.46 degrees
    {StepMode::Hybrid,
     Walls::Segments,
     {{-0x1.73ce01f8f8bap+4, 0x1.9bf53ba48cc18p-1}, {-0x1.6941fc9e60d88p+4, 0x1.6bb3dd55ce75cp+0}, {-0x1.687057c79f294p+4, 0x1.7ab9fb63b384ap+0}},
     {0x1.b009b3718a157p-4, 0x1.158a6d1a15e98p-1, 0x1.18b6ba8b42e66p-3},
     {{{-0x1.6d69ee0e5f3b9p+4, 0x1.2ea06937d01a6p+0}, {0x1.3a0cdd927faffp+1, -0x1.29ce9c69d6e3ap+2}, 0x0p+0, 0x1.884c21ba0d59p-2},
      {{-0x1.69a3d5a357dd5p+4, 0x1.673f314f0d5cap+0}, {0x1.685260b16a61ep+1, -0x1.975839827efb2p-2}, 0x0p+0, 0x1.835e6225fe32ep-1},
      {{-0x1.6c5028e57006ep+4, 0x1.3f208f609a1bep+0}, {-0x1.5aae17d3672c9p+1, 0x1.f7c54e73def32p+2}, 0x0p+0, 0x1.f7d0c13236a66p-2},
      {{-0x1.6e90878eeb1d6p+4, 0x1.1d1ab2a9b4231p+0}, {-0x1.9b3d4276083f2p+1, -0x1.d20aeca8423a7p+3}, 0x0p+0, 0x1.dfdf57859c35p-2},
      {{-0x1.6e8f161fd02cdp+4, 0x1.1d28da10c4e89p+0}, {-0x1.9f2f188086a5bp+3, 0x1.100892a22ac95p+1}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.6ba19db2f3f54p+4, 0x1.499a9af0cacabp+0}, {0x1.036588446850bp+0, 0x1.90d3326a7002bp+3}, 0x0p+0, 0x1.054ea745cdf1bp-3},
      {{-0x1.6d34aebbf8ce9p+4, 0x1.319d99281719bp+0}, {0x1.91a1e693423aep+3, 0x1.c11262a603fdep+2}, 0x0p+0, 0x1.58e1d7dd1eabp-2},
      {{-0x1.69f60d7859fe2p+4, 0x1.629cccae4732dp+0}, {0x1.9ce55eabdc367p+2, -0x1.52e1bfc2677f3p+1}, 0x0p+0, 0x1.c2187f94ca9adp-2}},
     {{0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
    // search seed 6, trial 86: an apex of 0.29 degrees
    {StepMode::Hybrid,
     Walls::Segments,
     {{-0x1.df0f6a8ab426ap+3, 0x1.f2013d87c6238p+2}, {-0x1.e00ff027bb682p+3, 0x1.efba415f103ffp+2}, {-0x1.eab8ef179b0c2p+3, 0x1.d4245f1c6c494p+2}},
     {0x1.59c343bc305f8p-2, 0x1.4e93a0fb69a36p-2, 0x1.1764fea8c8167p-1},
     {{{-0x1.e3c3fcf1d3b5ep+3, 0x1.e61a8d6258b2cp+2}, {0x1.e3ea984ac4559p+2, 0x1.acfc326e05a1p+0}, 0x0p+0, 0x1.7e91c0b355cecp-1},
      {{-0x1.e20638e19dfa6p+3, 0x1.ea6f0615e00e3p+2}, {0x1.afbd1df7df3fap+1, 0x1.1f03ca7845d94p+2}, 0x0p+0, 0x1.e745efdb91716p-1},
      {{-0x1.e3e112b5c927cp+3, 0x1.e5c3c611dd9c3p+2}, {-0x1.afd0148cae2f6p-3, -0x1.3fe0933e37756p+0}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.e1daa7f0bcf7p+3, 0x1.eaf7d525e33a9p+2}, {-0x1.25a3e6d5ea9a1p+2, 0x1.f05b7eec8f6afp+1}, 0x0p+0, 0x1.0f1dec13ef14fp-5},
      {{-0x1.e3f6cb88ce02p+3, 0x1.e5954a95d3328p+2}, {0x1.8eb9c734f7cp-1, -0x1.ebbefffe43624p+0}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.e3be85dab8f78p+3, 0x1.e621b62d6f15bp+2}, {-0x1.82e3133ff5d99p+0, 0x1.cb65b451d028dp+1}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.e2d3a6493a514p+3, 0x1.e86f0f19a33e8p+2}, {0x1.3fb82e387b6b1p+2, 0x1.7faaeed38970ap+2}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.e595455d2d6ccp+3, 0x1.e151ecc54293p+2}, {0x1.3512d1aacbb76p+2, 0x1.bb9c0a1088e39p+1}, 0x0p+0, 0x1.41bae282ec829p-5},
      {{-0x1.e506c48ce8f3ep+3, 0x1.e2bc63a1712d1p+2}, {0x1.d0c3293106b9ap+0, -0x1.c42b363089c5bp-1}, 0x0p+0, 0x1.058af630e1354p-1},
      {{-0x1.e5f5484a7ff38p+3, 0x1.e0696b076db7dp+2}, {0x1.00edf8cdfc148p+3, -0x1.1a3390abef17ep+3}, 0x0p+0, 0x1.bbe1c703ae0e3p-1},
      {{-0x1.e2ad02fb6f963p+3, 0x1.e8d9a79273dc9p+2}, {0x1.4c7d4bae75249p+1, -0x1.46ceb912ffce1p+3}, 0x0p+0, 0x1.16d05d9c8726bp-1},
      {{-0x1.e7091bd6988eap+3, 0x1.dda336342263cp+2}, {0x1.ca828542b3d72p+0, -0x1.a543db02eff77p+3}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.e1006d3f6b6e1p+3, 0x1.ed21016066a2dp+2}, {0x1.ca6e1ca36bf84p-2, 0x1.3fea07cf09468p-4}, 0x0p+0, 0x1.ff8cf42bb275fp-1}},
     {{0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}},
     0x0p+0},
    // search seed 6, trial 144: an apex of 0.62 degrees
    {StepMode::Hybrid,
     Walls::Segments,
     {{0x1.abd6d8a83e48fp+3, -0x1.90659afbdabdbp+1}, {0x1.a9e26889717e9p+3, -0x1.8db35301ff5edp+1}, {0x1.2cb57298d228ap+3, -0x1.8c6bfc8624372p+2}},
     {0x1.f5655cab5f4abp-2, 0x1.2e42816176fa8p-1, 0x1.f721851d4485ep-9},
     {{{0x1.68105829ede07p+3, -0x1.30b60f1865564p+2}, {0x1.bc270eb2ecfa4p+3, -0x1.8f2906464855fp+1}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.a2642632da56dp+3, -0x1.aaf94637eb9adp+1}, {0x1.614273d6205a9p+2, -0x1.fd2c1f0fce09bp+2}, 0x0p+0, 0x1.6028771efadb6p-2},
      {{0x1.70a3abbecdab9p+3, -0x1.2213812c538acp+2}, {0x1.d051c24e9eec1p+1, -0x1.a0cb3d9e46bf7p+2}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.85c22d6cd5e11p+3, -0x1.001a0389676c5p+2}, {0x1.5fa413d41a41p+3, -0x1.192afa9a221cep+3}, 0x0p+0, 0x1.c721524ba6034p-1},
      {{0x1.508148e25f358p+3, -0x1.542088f94f7dp+2}, {0x1.bdba2dfe815e5p+1, -0x1.88bae5fe2514p-1}, 0x0p+0, 0x1.382eae821a36ap-2},
      {{0x1.962d85ae04538p+3, -0x1.d1ca57abc62dp+1}, {0x1.f6249339776fbp+2, 0x1.5a4aecba5f5a8p+3}, 0x0p+0, 0x1.7ac964d0f7685p-2},
      {{0x1.7702eecf03ab4p+3, -0x1.185bec59f7119p+2}, {0x1.86184b91d0983p+1, 0x1.cbfdf55f10f2dp+1}, 0x0p+0, 0x1.995bb9c7c0cacp-1},
      {{0x1.95dea8141c19p+3, -0x1.d38218ecf9d28p+1}, {0x1.7fd47f4bee6cap+1, -0x1.fc91b8b92cc06p+1}, 0x0p+0, 0x1.050832c1d7ce3p-3},
      {{0x1.a99dff7e1971ap+3, -0x1.959f1a817edb3p+1}, {0x1.c4bbe1da82584p-1, -0x1.324c187207023p+2}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.8698dffcd5a86p+3, -0x1.00707c1f0c245p+2}, {0x1.62e26fcec5c9dp+1, 0x1.9d6a5a811b275p+1}, 0x0p+0, 0x1.7526a78ebb6e1p-2},
      {{0x1.6efec0b061befp+3, -0x1.24a04b7eaf481p+2}, {-0x1.fd385fec47277p+2, -0x1.fed27d4a5146dp+2}, 0x0p+0, 0x1.cb47f05a3dce8p-1},
      {{0x1.8ed3fed746623p+3, -0x1.e6f8f5e9d0205p+1}, {-0x1.ec5264fc0e413p-5, 0x1.76ed56b61915p+2}, 0x0p+0, 0x1.b417eb3882d8dp-1},
      {{0x1.945d1281a6464p+3, -0x1.d44cc10942104p+1}, {-0x1.6745cd2a23cd4p+2, 0x1.922a76cdb8c81p+2}, 0x0p+0, 0x1.2ff558e19d5ccp-1}},
     {{0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
};

// Both modes of each.
std::vector<Container> inEitherMode(std::span<const Container> containers) {
  std::vector<Container> out;
  for (const Container& c : containers) {
    for (StepMode mode : {StepMode::Hybrid, StepMode::Predictive}) {
      out.push_back(c);
      out.back().mode = mode;
    }
  }
  return out;
}

}  // namespace

TEST(PointsInNeedleApices, NoPointLeavesThroughTheTipInEitherMode) {
  const std::vector<Container> containers = inEitherMode(kNeedles);
  container_search::playEachChecked(containers.data(), containers.size());
}

TEST(PointsInNeedleApices, NoPointLeavesThroughTheTipOfTwoSegmentsInEitherMode) {
  const std::vector<Container> containers = inEitherMode(kNeedlesOfSegments);
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

// The joints of a needle of Segments are the world's, not the save's: a world loaded from the bytes of
// one just built holds the point in the tip too. So does a world whose sides were each destroyed and made
// again, and whose corners then each had a third Segment (a spur, so that no Segment there had one
// neighbour) until it was destroyed: it plays every step bit for bit as the world built once does.
TEST(PointsInNeedleApices, SegmentJointsSurviveSaveLoadAndRebuiltWalls) {
  for (const Container& c : inEitherMode(kNeedlesOfSegments)) {
    SCOPED_TRACE(c.mode == StepMode::Hybrid ? "hybrid" : "predictive");
    auto [built, bodies] = container_search::setUp(c);
    World loaded = World::load(built.save());
    World rebuilt(container_search::searchWorld(c.mode, c.gravityY));
    const BodyId walls = rebuilt.createBody({.type = BodyType::Static});
    const size_t n = c.corners.size();
    std::vector<FixtureId> sides;
    for (size_t k = 0; k < n; ++k) {
      sides.push_back(rebuilt.createFixture(walls, {.geometry = Segment{c.corners[k], c.corners[(k + 1) % n]},
                                                    .restitution = c.wallRestitution[k]}));
    }
    // Each side in turn gone and back: its neighbours forget it, and find it again.
    for (size_t k = 0; k < n; ++k) {
      rebuilt.destroyFixture(sides[k]);
      sides[k] = rebuilt.createFixture(walls, {.geometry = Segment{c.corners[k], c.corners[(k + 1) % n]},
                                               .restitution = c.wallRestitution[k]});
    }
    Vec2 centre{0, 0};
    for (const Vec2& corner : c.corners) centre += corner * (1.0 / static_cast<double>(n));
    std::vector<FixtureId> spurs;
    for (const Vec2& corner : c.corners) {
      spurs.push_back(rebuilt.createFixture(walls, {.geometry = Segment{corner, corner + (corner - centre) * 0.5}}));
    }
    for (FixtureId spur : spurs) rebuilt.destroyFixture(spur);
    const std::vector<BodyId> rebuiltBodies = container_search::throwBodies(rebuilt, c.bodies);
    for (size_t s = 0; s < c.steps.size(); ++s) {
      container_search::play(built, bodies, c.steps[s]);
      container_search::play(loaded, bodies, c.steps[s]);
      container_search::play(rebuilt, rebuiltBodies, c.steps[s]);
      for (size_t j = 0; j < bodies.size(); ++j) {
        const Vec2 p = built.position(bodies[j]);
        ASSERT_LE(container_search::distanceOutside(c.corners, p), 1e-9) << "body " << j << ", step " << s;
        ASSERT_LE(container_search::distanceOutside(c.corners, loaded.position(bodies[j])), 1e-9)
            << "loaded: body " << j << ", step " << s;
        const Vec2 r = rebuilt.position(rebuiltBodies[j]);
        ASSERT_TRUE(p.x == r.x && p.y == r.y) << "rebuilt: body " << j << ", step " << s;
      }
    }
  }
}
