// Points (radius 0) among disks and other points in closed containers under gravity, where a point lies
// on a wall's line: squeezed along a wall by a disk, at rest in a corner, or at rest on a wall that a
// neighbour strikes. A point has no overlap to tell which side of a line it is on, and the time of
// impact reads the side of one that moves along the line, or rests on it, from its acceleration: the
// side gravity presses it into. A point held inside by a wall that gravity pulls it away from (the
// ceiling of a corner, or a wall that a disk squeezes it along) was read as resting on that wall's outer
// side, slept or slid there, and left the container when it moved again. A point knows better (Support:
// the side of the face it last touched, and in a corner of that face the side of the other one), and a
// static face is never crossed, so such a contact from the other side is not taken. A random search
// (4 to 15 bodies, points and disks of radius 0.01 to 0.1, thrown at up to 15 units/s, 40 steps of 1/60
// to 1 s; 300 containers, each seeded on its own) found 12 and 15 containers of one Segment a side
// letting a body out (hybrid and predictive), and 13 and 12 closed Polylines, at 9299add; 4, 4, 6 and 3
// now. The containers, throws and steps are four that the search found (hex floats: round-off is the
// point); each lets a point out at 9299add.
#include <gtest/gtest.h>

#include <rattle/rattle.h>

#include <string>
#include <vector>

#include "container_search_support.h"

using namespace rattle;
using container_search::Container;
using container_search::Walls;

namespace {

const Container kContainers[] = {
    {StepMode::Hybrid,
     Walls::Segments,
     {{-0x1.bf6b2fe426bap+1, -0x1.de759c2592a02p+1}, {-0x1.047a82dd99a0ap+3, -0x1.1bcff853941f4p+0}, {-0x1.14626d9fbdc0fp+3, -0x1.9198d687c6b32p+2}, {-0x1.bf1f67ee3c33dp+1, -0x1.f14a4168bdf75p+1}},
     {0x1.7dcd3e84cf5b2p-2, 0x1.04e0e5d83188dp-1, 0x1.8f5c31c96fd75p-3, 0x1.5cbbc39cfb7c7p-2},
     {{{-0x1.47cea0ff46e95p+2, -0x1.21e412d41d0cap+2}, {0x1.3bc3c9eddf244p+3, -0x1.1008946ad9bbep+2}, 0x1.bf5df6de41fbap-5, 0x1.19799812dea11p-40},
      {{-0x1.b9ea5b8f25c15p+2, -0x1.65000fd053a08p+1}, {0x1.0b968e0c823cdp+1, -0x1.3438c1cb68fd2p+3}, 0x0p+0, 0x1.b04225dec60f7p-5},
      {{-0x1.9a72166b2ac89p+2, -0x1.a509da66b59a5p+1}, {-0x1.ef0f6e03aabcfp+2, 0x1.bd8b3bacf87f3p+1}, 0x0p+0, 0x1.d39cddf5e3b67p-6},
      {{-0x1.86c1c3e901e56p+2, -0x1.e50fdf409998p+1}, {0x1.284a45fcb1886p+0, 0x1.ad541fbe364aep+2}, 0x1.5925a69051e31p-4, 0x1.19799812dea11p-40},
      {{-0x1.f0d9ae1e4f92ep+1, -0x1.cbefaebf0dc26p+1}, {-0x1.273ab32c8cbdp+3, 0x1.0b40eb0ebb8cdp+3}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.3dae6b008c222p+2, -0x1.e4dc88ccf59aep+1}, {0x1.bf9c93b46c841p+2, 0x1.2722b1830297bp+3}, 0x0p+0, 0x1.2b4632b413268p-1},
      {{-0x1.0c5ec3d4e63b9p+2, -0x1.06db3c5db5595p+2}, {-0x1.1fac3649d1033p+2, 0x1.db4d4fd194dfbp-1}, 0x0p+0, 0x1.af3ddc0e5d4fcp-1},
      {{-0x1.27f9a55c68ad4p+2, -0x1.d69d5bfefa3a2p+1}, {-0x1.3959fb835d1a1p+3, 0x1.497b736a92b94p+3}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.a8cfdde1379dp+2, -0x1.de2a7c079bfcp+1}, {-0x1.8c8d187f95f17p+3, -0x1.5dd9fa3e750a4p+2}, 0x0p+0, 0x1.459d710bf9b86p-2},
      {{-0x1.63ce8881fff11p+2, -0x1.dc66578d3c455p+1}, {0x1.37107a7867078p+3, 0x1.4f6a2971b6d67p+3}, 0x0p+0, 0x1.4a43282633f5ap-1},
      {{-0x1.84a22a2f38f81p+2, -0x1.df3201a1aadc9p+1}, {0x1.c13baf9561bb8p+0, 0x1.079b00c2351c2p+3}, 0x0p+0, 0x1.19799812dea11p-40}},
     {{0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, 6, {-0x1.c02cadfa3bfa7p+1, -0x1.06542ed50c711p+1}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, 3, {-0x1.03e1bbea7714dp+3, 0x1.412a288d2e6b3p+3}},
      {0x1.1111111111111p-6, 2, {-0x1.2191f34d78495p+2, 0x1.d093057d9f53ep+2}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, 3, {0x1.141d9af32fdedp+0, -0x1.aa96fe3e2eb3ep+1}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, 4, {0x1.38097ada44d55p+3, -0x1.ac69a158c44d8p+1}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}}}},
    {StepMode::Predictive,
     Walls::Segments,
     {{0x1.b8dad10bb93ecp+3, -0x1.ea39848c5bad9p+2}, {0x1.355ce67cf53c6p+3, -0x1.f2b5bab99966cp+2}, {0x1.989d18f89d2e8p+2, -0x1.5129ca3206b6p+3}, {0x1.75b79e0cad634p+2, -0x1.76b4cc38f25dep+3}, {0x1.24cded4f9a898p+4, -0x1.d50a6b8435859p+3}},
     {0x1.5cd66f7c3a223p-1, 0x1.9ff9fcb3b2c93p-4, 0x1.bb979a9009474p-3, 0x1.967029d8b945dp-2, 0x1.82c462ba70149p-1},
     {{{0x1.692d64ee91cap+3, -0x1.81a6b7ca19a99p+3}, {-0x1.b3900f5e2ab9fp+1, 0x1.1b3e7f785532ep+2}, 0x0p+0, 0x1.adb6d852d125dp-1},
      {{0x1.90d461821466fp+3, -0x1.5ece61e2c1f8bp+3}, {-0x1.d26393e87383p+2, 0x1.80fb7335d2488p-1}, 0x0p+0, 0x1.cfc169074636ap-1},
      {{0x1.3078d9a5d6b6p+3, -0x1.3d7e8252d25cfp+3}, {0x1.b6c94f1f051f9p+2, -0x1.ea105253516d3p+2}, 0x1.45a13d77a87c5p-5, 0x1.604b55409f4bcp-1},
      {{0x1.668f37fe7f841p+3, -0x1.50267ebbd6115p+3}, {-0x1.f28e873c21b04p+2, 0x1.4b96f14e9373bp+1}, 0x0p+0, 0x1.f3f430d885c6cp-7},
      {{0x1.4239edd17e4fep+3, -0x1.3ced4b8ade9cbp+3}, {0x1.c3f970b4439a4p+2, 0x1.3edc248941c2ap+1}, 0x0p+0, 0x1.0a45866b700ccp-1},
      {{0x1.4c0abce47de97p+3, -0x1.36b62d27e990ap+3}, {-0x1.1500ccfb5c59ap+0, -0x1.52165838c5083p+2}, 0x0p+0, 0x1.afc1489d982c6p-1},
      {{0x1.68413c9adc1e2p+3, -0x1.7c2205e13061bp+3}, {0x1.8792353d32808p+1, 0x1.8d823619bfae5p+2}, 0x0p+0, 0x1.e20aebceffcdp-1},
      {{0x1.a6dad374f67f1p+3, -0x1.5f92170e40df9p+3}, {0x1.4fb5d9c6b1c88p+3, -0x1.d508144e2536cp-2}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.75931a3a0f117p+3, -0x1.5a56b09e41723p+3}, {-0x1.529010b1df26bp+3, -0x1.97a2a376854bp+1}, 0x0p+0, 0x1.bbed7822504d9p-1},
      {{0x1.0826b6bb47ep+3, -0x1.48c6014bd2609p+3}, {0x1.1f8df7d0ea921p+2, -0x1.bcf2fce64c386p+1}, 0x1.4b3faf1f7dddbp-4, 0x1.19799812dea11p-40},
      {{0x1.3fc5d9139cb6ap+3, -0x1.5228df88eadd2p+3}, {-0x1.846d2567bae7cp+1, 0x1.5a97c83777a6ep+0}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.94df53e352504p+3, -0x1.5e56bbe00d7cfp+3}, {-0x1.09a7356ba10d2p+3, -0x1.3daa7458d2e4ap+2}, 0x0p+0, 0x1.0c1ec8a0b0fa7p-7},
      {{0x1.5efcd77e8873bp+3, -0x1.5253938087944p+3}, {-0x1.22b4ef3adc8bcp+3, -0x1.23c0e2ada1b74p+2}, 0x0p+0, 0x1.00f646a1b3e3fp-3}},
     {{0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, 5, {0x1.fbc0ff53a353bp+2, -0x1.a652f89a0da59p+1}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
    {StepMode::Hybrid,
     Walls::Polyline,
     {{-0x1.9db8a3ed119bbp+4, -0x1.85d6fc3189704p+3}, {-0x1.9ffc0fc29aaabp+4, -0x1.846d182255016p+3}, {-0x1.af00e4690e1d5p+4, -0x1.8079e8a579f9cp+3}, {-0x1.d63636f5fa71dp+4, -0x1.a75f4e5e06f8ap+3}, {-0x1.d6ba4cabf637fp+4, -0x1.a8b3f0845c719p+3}},
     {0x1.fc1c2d9e99c35p-2},
     {{{-0x1.b14ac6016cd0ap+4, -0x1.8ceab10a4742p+3}, {0x1.022e990d36104p-4, 0x1.bc8da751ec5ecp-3}, 0x0p+0, 0x1.1e0b815ed60cep-4},
      {{-0x1.a96cfb4829349p+4, -0x1.882338046b21ap+3}, {0x1.fbe32d653cb2dp+0, 0x1.cfa3b117058e1p+0}, 0x0p+0, 0x1.7922f07288f3fp-1},
      {{-0x1.bbfc18f49d773p+4, -0x1.93ce088ccdf94p+3}, {-0x1.b7f80d8ecf4a4p+3, 0x1.a80a11707244fp-1}, 0x0p+0, 0x1.771f5c321a8e6p-2},
      {{-0x1.b6e2a966eb7f1p+4, -0x1.90900bf54cba3p+3}, {0x1.fbb483a609cc8p+2, -0x1.5a6151f3944dap+2}, 0x0p+0, 0x1.8d08f5c725d82p-1},
      {{-0x1.bb9a6a470808dp+4, -0x1.96b9ac1c72f6ap+3}, {-0x1.b43d6640df994p-3, 0x1.656dc2088df3p+1}, 0x0p+0, 0x1.dd9b42a0ba353p-1},
      {{-0x1.beaa9e398f2c3p+4, -0x1.96e96d9862a15p+3}, {0x1.ec94b0de03c57p+2, -0x1.127dab17931b5p+0}, 0x0p+0, 0x1.2ca791438024p-5},
      {{-0x1.b3dc2f8c0c5a8p+4, -0x1.91e324b4b6e0dp+3}, {0x1.41974aef02f1ep+3, -0x1.4e57ea0b07195p-1}, 0x0p+0, 0x1.2450aeb3b3402p-1}},
     {{0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, 2, {-0x1.36dfd942317cep+1, 0x1.a7ea964e5d431p+1}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
    {StepMode::Predictive,
     Walls::Polyline,
     {{0x1.f2c882ec01369p+4, -0x1.68cfde5bc19f9p+4}, {0x1.ec6c4e6c423b1p+4, -0x1.6171700412df2p+4}, {0x1.8dfe197de6c56p+4, -0x1.37f0673a0f2eap+4}, {0x1.753a3293f1a8ap+4, -0x1.3a249ec814323p+4}, {0x1.1c48a930bd144p+4, -0x1.7920af4bf2d74p+4}, {0x1.19c8e94f4ef0cp+4, -0x1.f69fc223830d5p+4}},
     {0x1.418d4e1d61984p-1},
     {{{0x1.8147d04af3602p+4, -0x1.6a8e71c265695p+4}, {0x1.64abe022210ffp+0, 0x1.038f474a88ea8p+3}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.6f4948f93d72p+4, -0x1.82cbf6fea382fp+4}, {0x1.2d082d007196cp+3, -0x1.7a14fc4f8c9c7p+1}, 0x0p+0, 0x1.845453177dca3p-1},
      {{0x1.71c3fbca71bbcp+4, -0x1.85239548f0de4p+4}, {-0x1.b4ae71e2ff154p+3, -0x1.be369052efc05p+1}, 0x0p+0, 0x1.1577e683c3c1ap-3},
      {{0x1.8130ec16a5771p+4, -0x1.776be3849a493p+4}, {0x1.56bc73b544fc6p+1, -0x1.793effa3f7186p+1}, 0x0p+0, 0x1.6b947e96760efp-1},
      {{0x1.8dd7772cee781p+4, -0x1.7197af5cad8bbp+4}, {0x1.955f4fd374908p+1, 0x1.680a10e059adp-3}, 0x0p+0, 0x1.6da0be34c8dd1p-3},
      {{0x1.90d8cb6309b32p+4, -0x1.6136ec8386b8ap+4}, {0x1.cc994bcdf4dbep+2, -0x1.03c7da75a720cp+2}, 0x0p+0, 0x1.c68726b8cb33p-2},
      {{0x1.5ee04f05fe4ccp+4, -0x1.800d82e423bb1p+4}, {0x1.c74c5e297187bp+2, -0x1.cbe1b77c19181p+2}, 0x0p+0, 0x1.be999781f4dbbp-3},
      {{0x1.74c598a941a26p+4, -0x1.710cfcca63877p+4}, {0x1.38c0e6d715d4cp+0, -0x1.05c210a80b8ep+0}, 0x0p+0, 0x1.5e1fb591c6fd2p-1},
      {{0x1.999f2fc5895f5p+4, -0x1.7347d507a7afp+4}, {-0x1.0f9a4223d7e5p+2, -0x1.f965bea523567p+2}, 0x1.520981ae39e86p-4, 0x1.19799812dea11p-40},
      {{0x1.880e2ca7fb849p+4, -0x1.633344d1eb089p+4}, {0x1.30b67a50fa476p+1, -0x1.0bdda9e438b0fp+2}, 0x1.428a7e2275721p-4, 0x1.c3554ac83ff3dp-2},
      {{0x1.8df1e868cfd26p+4, -0x1.57d3875cc900ep+4}, {0x1.bf2a49218a6c6p-3, 0x1.8e2a499b1447cp+2}, 0x1.8a7d3ab0648d9p-4, 0x1.19799812dea11p-40},
      {{0x1.7cf4d277f653fp+4, -0x1.5a34e6544efd4p+4}, {-0x1.0a4fa6e79a5f6p+3, 0x1.1d0361da9edc6p-1}, 0x1.d6e1177f3b8a4p-6, 0x1.347a3764f39p-3},
      {{0x1.79653f6633863p+4, -0x1.7fed14a4b7daap+4}, {-0x1.679ffbebf902ap+3, -0x1.bfadf0bf7452ap-1}, 0x0p+0, 0x1.c27299e372d6fp-5},
      {{0x1.8c3d10eeced0ep+4, -0x1.6f4ad565fef97p+4}, {0x1.4ce85ff1bf95ep+2, 0x1.62e386f5d16c4p+3}, 0x0p+0, 0x1.74d84969e26cp-2},
      {{0x1.8c203bd49e1edp+4, -0x1.6907e9494c91fp+4}, {0x1.b0a54a244b20dp+3, -0x1.54590f0ca701cp+2}, 0x0p+0, 0x1.936e403464cccp-4}},
     {{0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, 6, {-0x1.4ee3da8c810d5p+1, 0x1.6d7e105828575p-1}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, 13, {0x1.3034d0aafefdep+1, -0x1.94fd8efbecbb6p-2}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, 0, {0x1.0432fb7d61888p-1, -0x1.12877c153b4d2p-3}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
};

}  // namespace

TEST(PointsOnWalls, NoBodyLeavesAContainerWhereAPointLiesOnAWall) {
  for (size_t i = 0; i < std::size(kContainers); ++i) {
    const Container& c = kContainers[i];
    SCOPED_TRACE("container " + std::to_string(i));
    auto [w, bodies] = container_search::setUp(c);
    for (size_t s = 0; s < c.steps.size(); ++s) {
      container_search::play(w, bodies, c.steps[s]);
      for (size_t j = 0; j < bodies.size(); ++j) {
        ASSERT_LE(container_search::distanceOutside(c.corners, w.position(bodies[j])), 1e-9)
            << "body " << j << " (radius " << c.bodies[j].radius << "), step " << s;
      }
    }
  }
}
