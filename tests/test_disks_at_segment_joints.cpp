// Disks in closed containers of one Segment a side, under gravity. A bare Segment's ends hold nothing
// (README, Geometry), so a stepped body (an island's member) beside the joint of two Segments, past the end
// of one of them, had no contact with it, and its straight path through the rest of the step crossed that
// Segment's face: a random search at 54f7f51 (4 to 15 disks of radius 0.01 to 0.1 thrown at up to 15
// units/s into random convex containers, steps of 1/60 to 0.1 s) found 11 of 150 containers letting a
// disk out in the hybrid mode and 8 in the predictive mode (35 and 26 with steps of up to 1 s). The
// solve now holds such a crossing, found by the member's time of impact along its solved path, as a
// contact with the face it meets (holdSegmentCrossings). The containers, throws and steps are those
// the search found (hex floats: round-off is the point).
#include <gtest/gtest.h>

#include <rattle/rattle.h>

#include <string>
#include <vector>

#include "container_search_support.h"

using namespace rattle;
using container_search::Step;
using container_search::Throw;

namespace {

struct Container {
  StepMode mode;
  std::vector<Vec2> corners;  // counter-clockwise, convex; one Segment a side
  std::vector<double> wallRestitution;
  std::vector<Throw> bodies;
  std::vector<Step> steps;
};

const Container kContainers[] = {
    {StepMode::Hybrid,
     {{-0x1.6132528eb102p+0, -0x1.6e65a200ba3a3p+4}, {-0x1.ab6083c554a6fp+2, -0x1.2d66671d05219p+4}, {-0x1.5c722e23ffabp+2, -0x1.0fc96d46f91a2p+5}, {-0x1.9243f44dd4848p+0, -0x1.ea3c527c3450dp+4}, {-0x1.df5f57bad0f6p-2, -0x1.aad055384293p+4}},
     {0x1.bacf2e2e6b867p-1, 0x1.84dfcf505f218p-1, 0x1.78d8ca52fe5b8p-3, 0x1.01eb45ceffeebp-5, 0x1.5d79d70028693p-1},
     {{{-0x1.979c9d1acf867p+1, -0x1.b74d696033fdfp+4}, {0x1.2c8a9de0bd163p+3, 0x1.b6e7929ffaf21p+0}, 0x1.bec9f494a24b6p-5, 0x1.4779361e20921p-1},
      {{-0x1.70de709561074p+1, -0x1.9de03cadaeb0ap+4}, {0x1.ad639a56ab285p-2, -0x1.961413c0d887ap+1}, 0x1.3bb82e30806dp-4, 0x1.945daadd8983cp-1},
      {{-0x1.e0dcc3dff27c9p+1, -0x1.95204ecce989dp+4}, {0x1.6cc3c4547bbdcp+1, -0x1.35ba9f1f3514ap+2}, 0x1.0fababd9b7f26p-4, 0x1.19799812dea11p-40},
      {{-0x1.933295de45b11p+1, -0x1.b2e284e1a8f49p+4}, {-0x1.7969911dea28ep+3, 0x1.cb2468ddaf485p+0}, 0x1.4b1146b02f37ap-5, 0x1.19799812dea11p-40},
      {{-0x1.05fa8626607b9p+1, -0x1.9c4cd05235a74p+4}, {0x1.567701cabbb97p+1, 0x1.99019cc1b239ap+0}, 0x1.024134cff2622p-6, 0x1.19799812dea11p-40},
      {{-0x1.7897f1f1c94abp+1, -0x1.942846c1920bap+4}, {-0x1.1177437563872p+2, 0x1.226b01d01f364p+2}, 0x1.3e129106d1f5dp-5, 0x1.19799812dea11p-40}},
     {{0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, 2, {0x1.f11ba5e6f562ap+2, 0x1.b404bb8b28f7p+2}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, 0, {0x1.e8943ccf7b097p+1, 0x1.0afaece3652a3p+1}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}}}},
    {StepMode::Hybrid,
     {{-0x1.40c5375b71381p+4, -0x1.22eb60d434dcdp+4}, {-0x1.4940d1e585ca9p+4, -0x1.29b6df7e8a78bp+4}, {-0x1.24d14287a58d6p+4, -0x1.b50446965f6a1p+4}, {-0x1.10bb5e20dea1bp+4, -0x1.b728235fef127p+4}, {-0x1.f67f65615cb3dp+3, -0x1.b3dd83e977464p+4}, {-0x1.e2f33e2702b9cp+3, -0x1.b04cc6c40a0cbp+4}},
     {0x1.22f18c5aeada4p-6, 0x1.c3e5477963d3ep-2, 0x1.39eb099d79f05p-1, 0x1.dc6fac774674fp-1, 0x1.e48455469c15cp-2, 0x1.10e59f318aa1dp-1},
     {{{-0x1.201366fbfde5cp+4, -0x1.8aa90218d2419p+4}, {-0x1.e8b222af379f6p-6, 0x1.286b311ccf081p+2}, 0x1.1da0e57b63cddp-5, 0x1.2d93c1f77851ep-1}},
     {{0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, 0, {-0x1.2be582af921eep+0, -0x1.22ced31323b6p+3}},
      {0x1.1111111111111p-6, 0, {0x1.55634f8c532cdp+2, -0x1.0992bce7f3a7ap+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, 0, {0x1.26f87106e4e18p+0, 0x1.2835d86158d4dp+3}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, 0, {-0x1.0474177f2bc5fp+3, -0x1.7af561ada4c3dp+1}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, 0, {0x1.fc318cb26e853p-1, -0x1.a1624b20c9eafp+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
};

}  // namespace

TEST(DisksAtSegmentJoints, NoSteppedDiskCrossesTheNextSegment) {
  for (size_t i = 0; i < std::size(kContainers); ++i) {
    const Container& c = kContainers[i];
    SCOPED_TRACE("container " + std::to_string(i));
    World w(container_search::searchWorld(c.mode));
    const BodyId walls = w.createBody({.type = BodyType::Static});
    const size_t n = c.corners.size();
    for (size_t k = 0; k < n; ++k) {
      w.createFixture(walls, {.geometry = Segment{c.corners[k], c.corners[(k + 1) % n]}, .restitution = c.wallRestitution[k]});
    }
    const std::vector<BodyId> bodies = container_search::throwBodies(w, c.bodies);
    for (size_t s = 0; s < c.steps.size(); ++s) {
      container_search::play(w, bodies, c.steps[s]);
      ASSERT_FALSE(w.stats().eventBudgetReached) << "step " << s;
      for (size_t j = 0; j < bodies.size(); ++j) {
        // The centre stays a radius inside every wall, less what the solve may leave (3e-5 of a radius).
        const double r = c.bodies[j].radius;
        ASSERT_LE(container_search::distanceOutside(c.corners, w.position(bodies[j])), -r + 1e-4 * r + 1e-9)
            << "body " << j << ", step " << s;
      }
    }
  }
}
