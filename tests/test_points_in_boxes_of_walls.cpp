// Points in a box of four Polygon walls (the world_api fuzz target's third kind of container, here turned
// by a random angle), thrown about under gravity with steps of 1/60 to 1 s. A random search at d83b1af
// found 5 to 10% of such boxes, with 4 to 15 points and small disks each, letting a point out (the
// predictive and the hybrid mode), and 3 of 400 with one point each (hybrid):
//  - a point sliding on a sloped face, its normal velocity and acceleration round-off, met the face it
//    slid on at once: dismissed and predicted again at that instant until the step's budget of
//    predictions ran out, it then met no wall for the rest of the step (faceImpact takes a point on a
//    face's line moving along it as meeting it at no time, as segmentImpact does);
//  - a point in the corner of the floor and a wall, moving along the floor into the wall, was taken as
//    leaving every face of the wall because it left the wall's bottom face, which lies on the floor's
//    line (featureLeftByPoint names the one face left).
// The boxes, throws and steps are those the search found (hex floats: round-off is the point).
#include <gtest/gtest.h>

#include <rattle/rattle.h>

#include <cmath>
#include <string>
#include <vector>

#include "container_search_support.h"

using namespace rattle;
using container_search::Step;
using container_search::Throw;

namespace {

struct WalledBox {
  StepMode mode;
  Vec2 centre;
  double halfWidth, halfHeight, thickness, angle, gravity;
  double wallRestitution[4];
  std::vector<Throw> bodies;
  std::vector<Step> steps;
};

const WalledBox kBoxes[] = {
    {StepMode::Hybrid, {0x1.2d9dcb691e662p+4, -0x1.51cc895f1b5ccp+2}, 0x1.7fef6a177fcf8p+0, 0x1.104de798ea4e4p+2, 0x1.1519f24f3f2f8p-1, 0x1.5baebe3a3b9c6p+2, -0x1.39eb851eb851fp+3,
     {0x1.11968c1ad9149p-3, 0x1.17c97f31e0a49p-3, 0x1.c67176289b782p-1, 0x1.ca1ee09f120a7p-1},
     {{{0x1.2afceb99b6e73p+4, -0x1.5cba686e5757fp+2}, {-0x1.8db44afe79859p+1, -0x1.3d09536989e72p+3}, 0x0p+0, 0x1.5dfa4d3bb8d1bp-4}},
     {{0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, 0, {-0x1.82d5f91c087efp+2, -0x1.92b936cb29fbap+2}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, 0, {0x1.db0efd5a4c9d5p+1, -0x1.342fba9c2f8cp+2}},
      {0x1p+0, 0, {-0x1.0a46938974de1p-2, -0x1.18ff0e3443b49p+1}}}},
    {StepMode::Hybrid, {0x1.4bd6831a76b24p+3, -0x1.1c63379a65db2p+3}, 0x1.1021d92adb40ap+2, 0x1.8cef0cd34df76p+1, 0x1.3c04e4739a9a7p-1, 0x1.1b7cb40f24ac6p+1, -0x1.39eb851eb851fp+3,
     {0x1.add8f44c85ac8p-6, 0x1.78d3b682ce76p-3, 0x1.6ce3f82ab09a6p-1, 0x1.842f3dea987aep-1},
     {{{0x1.3d12feef6f93ap+3, -0x1.fed24ef27e5f7p+2}, {-0x1.79ff232419eafp+1, -0x1.0a02132417bfdp+1}, 0x0p+0, 0x1.c8a898595dc71p-2}},
     {{0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, 0, {-0x1.7c17266b9a15p+2, -0x1.1e8b02ff92c18p+2}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, 0, {-0x1.92b22557124eep+0, -0x1.58ada1611d50bp+2}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, 0, {0x1.8494bb45c1d28p+1, -0x1.3a3d9a3c66acap+2}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
    {StepMode::Hybrid, {-0x1.35006da7a81cep+4, -0x1.7559341f17734p+4}, 0x1.ffc4146f66941p+1, 0x1.c091abef1fcb3p+1, 0x1.6a5ac123ccc78p-2, 0x1.b66853b85ad0ap-1, -0x1.39eb851eb851fp+3,
     {0x1.5c3a9f6421b6dp-1, 0x1.a1f59dac7d1a5p-1, 0x1.0bee1701d15c9p-2, 0x1.5b5604a87e2f9p-2},
     {{{-0x1.181667d5112dp+4, -0x1.47db56322d0d3p+4}, {-0x1.dcc6041e143p+2, -0x1.960de874f51abp+1}, 0x0p+0, 0x1.19799812dea11p-40}},
     {{0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, 0, {-0x1.73d5be5c99374p-3, -0x1.5d899d0205802p-2}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, 0, {0x1.19d0c2d0807a3p+1, -0x1.b0a1351cd9debp+2}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
    {StepMode::Predictive, {-0x1.ab8a8e1a4f914p+2, -0x1.55e0242b337e4p+3}, 0x1.dd32579fb5543p+0, 0x1.8880107fa7271p+1, 0x1.48e46ac79560ap-1, 0x1.444de7d787789p+1, -0x1.39eb851eb851fp+3,
     {0x1.c1c9f0069b1dp-1, 0x1.f2cadb5d5fa33p-2, 0x1.8f6851b88039ep-1, 0x1.6352219fefb35p-1},
     {{{-0x1.5bf5d66035732p+2, -0x1.7487dcb14c1ffp+3}, {-0x1.0e30dc903b4d2p-1, -0x1.57558611ac576p-3}, 0x0p+0, 0x1.e5b2d39da7799p-1},
      {{-0x1.87d7e407a8172p+2, -0x1.58180be97432ap+3}, {-0x1.2da954e355d83p+3, 0x1.f03a0b9060438p+2}, 0x1.98e2bebdc9b7ap-5, 0x1.19799812dea11p-40},
      {{-0x1.d094e80e898b3p+2, -0x1.6c00b1c718904p+3}, {-0x1.17344cb1729edp-3, -0x1.53ae01f3619ep+2}, 0x1.4f26406b10b61p-5, 0x1.2731cbf8e160bp-3},
      {{-0x1.a2d5a5a21d951p+2, -0x1.312afa83dca82p+3}, {0x1.634ea2796d745p+3, 0x1.0912b875bdbf4p+3}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.9021f2d93e8dap+2, -0x1.4f15afa46e30cp+3}, {-0x1.6b71d63b0004p-3, 0x1.f245b2cb031ddp+0}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.6026ffed80b06p+2, -0x1.28620e6d6ff58p+3}, {0x1.0431e922ad1a8p+3, -0x1.2a714f252d084p+0}, 0x1.6da34ebcc5cp-5, 0x1.56a5826917a71p-1},
      {{-0x1.9e2d12df8b033p+2, -0x1.45e3f9755bb07p+3}, {-0x1.1eee2a870562p-1, -0x1.efea90e178fa4p-2}, 0x0p+0, 0x1.b457f72175021p-3},
      {{-0x1.1033e7099ff01p+3, -0x1.7e7ca0abc64e2p+3}, {0x1.bede4dcc2742ep+2, 0x1.3e96606e00008p+3}, 0x1.347a63421915bp-5, 0x1.a8287c1bd1d91p-1},
      {{-0x1.b59e9145ef0aep+2, -0x1.30b40af59facfp+3}, {0x1.ea9ac629b2386p+1, 0x1.a19c94542585bp-2}, 0x1.52c8b7faf9cc9p-4, 0x1.19799812dea11p-40},
      {{-0x1.a7a63d10f6c77p+2, -0x1.443353da2f5aap+3}, {-0x1.cb6513e76b51fp+2, -0x1.16aba4b86ff5bp+2}, 0x0p+0, 0x1.6337e4ed630dp-3},
      {{-0x1.e67b8228ffc59p+2, -0x1.5aff84fdfdf3ep+3}, {0x1.ad12ab32b8f18p-1, -0x1.c10f7bfadd798p+3}, 0x1.2dfbb02ba4557p-4, 0x1.2c0f6432d259ap-2},
      {{-0x1.82d57e756aad3p+2, -0x1.587334b08da45p+3}, {0x1.7de23f83ebde6p+3, 0x1.213ce79b25572p+3}, 0x0p+0, 0x1.a1c56585aeb0fp-1},
      {{-0x1.dc95b5e370c8ep+2, -0x1.72f8da941b4cp+3}, {0x1.9f145120bbffap+2, -0x1.7e17a619345c7p+2}, 0x0p+0, 0x1.95c083173a2d1p-2},
      {{-0x1.d0857ecd9c044p+2, -0x1.5451e8ea370cp+3}, {0x1.521b660ee18e9p+1, -0x1.1d7a41bb513fdp+3}, 0x0p+0, 0x1.78032e5ab946cp-1},
      {{-0x1.a369dbaa45787p+2, -0x1.5050f256ba076p+3}, {0x1.7a7d5e7ee1a17p+2, -0x1.306552bae6967p+3}, 0x0p+0, 0x1.19799812dea11p-40}},
     {{0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, 0, {-0x1.76a0132157af5p+3, 0x1.72b1e6e919fcbp+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
    {StepMode::Predictive, {-0x1.ee8c5bf5b2e68p+1, 0x1.957a6ff5b698cp+4}, 0x1.114579fbc73a5p+1, 0x1.f5946ce8a017p+0, 0x1.00035517c42b3p-1, 0x1.203dbc706fbbep+2, -0x1.39eb851eb851fp+3,
     {0x1.f38667cb9929fp-1, 0x1.169486cc2b3bbp-1, 0x1.97a53399b4337p-2, 0x1.ff694f57abcadp-2},
     {{{-0x1.0440ba028417bp+2, 0x1.9cfc44e0b52fdp+4}, {-0x1.8b4180c53944p+0, 0x1.67bf26a2cd21ep-1}, 0x0p+0, 0x1.9e419e44fb21p-1},
      {{-0x1.54e4b07aac26bp+1, 0x1.981fa2da24bb1p+4}, {0x1.4d5dcd3d09237p+3, 0x1.ff8766743fa14p+2}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.2a5ad47fda8bdp+2, 0x1.8bfdfee7bdb6bp+4}, {-0x1.d329e33d821a6p+2, 0x1.8cd14d03f8cecp+3}, 0x1.656f8251024a9p-5, 0x1.7c8e839ea81dfp-1},
      {{-0x1.eac904fcd1197p+1, 0x1.908128878d864p+4}, {0x1.8f6e432e8ecc7p+3, 0x1.99960fc98dcb2p+2}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.94c074780f9d4p+1, 0x1.90eb3f07d9221p+4}, {0x1.160841616c797p+1, 0x1.551accc163812p+1}, 0x0p+0, 0x1.a9f4a943399c8p-1},
      {{-0x1.c2eaf70c4ab43p+1, 0x1.92579a5c596cdp+4}, {0x1.ed4965daf3b7dp+0, 0x1.1565865a6dde8p+3}, 0x0p+0, 0x1.19799812dea11p-40}},
     {{0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, 3, {0x1.3671c4b359e84p-1, -0x1.2fd48ee1a3971p+2}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, 1, {0x1.3560a54124733p+1, 0x1.b7f5505a3d762p+1}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, 2, {-0x1.d090b3db77798p-1, -0x1.d6d77b346762p-2}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
    {StepMode::Hybrid, {-0x1.9ce066b9802dcp+2, 0x1.7f8d51bacda36p+4}, 0x1.2915bd975da77p+2, 0x1.ccd7bf89bca24p+0, 0x1.0db52c0db5899p-1, 0x1.4160f2f25d099p+0, -0x1.39eb851eb851fp+3,
     {0x1.2f6ec38741207p-6, 0x1.4ff886e7c10bep-3, 0x1.4ffb6fd0003bcp-1, 0x1.ca86851c915aep-1},
     {{{-0x1.a17dc1f0bdb39p+2, 0x1.848cb3742762ap+4}, {-0x1.4729d17b6fbap+2, -0x1.df5bfb9863a22p+2}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.d970bfa90175ep+2, 0x1.6add6d1abba98p+4}, {0x1.852fa9776a6aap+2, -0x1.89e86ce5d28c1p+1}, 0x1.5dcfa8230635p-5, 0x1.b85086eb5f84fp-1},
      {{-0x1.27c0a9bd17e26p+2, 0x1.b55f17faf94e5p+4}, {-0x1.891ef72757ce8p+1, 0x1.6b3d9c1ab8224p+3}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.78de726a30f06p+2, 0x1.6383887616eadp+4}, {-0x1.21a0e1ede5082p+0, 0x1.5865e0f483a12p+0}, 0x0p+0, 0x1.0f3e298d61d47p-1},
      {{-0x1.c28efb7cf69c4p+2, 0x1.75764f121b7d9p+4}, {-0x1.2c15e6c4b8069p+2, 0x1.27d9c1a5f9baep-1}, 0x0p+0, 0x1.f1a37076d1cbp-1},
      {{-0x1.89bc0c9e54efdp+2, 0x1.69a67c4e74e4ep+4}, {0x1.f714a84012e38p-1, -0x1.0c2fb770342d9p-8}, 0x0p+0, 0x1.4bb3cd5e28ca5p-1},
      {{-0x1.a66617e181d3fp+2, 0x1.8394a3f7d18e8p+4}, {0x1.163362b45bb87p+0, 0x1.433c7344d9b6bp+0}, 0x1.5e7092bea41c2p-4, 0x1.41a24813dad7fp-4},
      {{-0x1.5cf32f93afefdp+2, 0x1.a116d70fafe51p+4}, {-0x1.0a69e6c2122b6p+3, 0x1.80a62dae22e82p+2}, 0x0p+0, 0x1.6eb667e8cf54fp-2},
      {{-0x1.695845273b093p+2, 0x1.a0a87ebbff1dcp+4}, {0x1.5631a3adb3007p+0, -0x1.fe9e4c96cb628p+1}, 0x1.6ee4b7b9aa726p-6, 0x1.b07d1bb0528fdp-2},
      {{-0x1.b2153a4182ccfp+2, 0x1.79f84ad69160ep+4}, {0x1.9015d1ae46269p+3, -0x1.1678c38a301d3p-1}, 0x0p+0, 0x1.048ce69b7ccb4p-1},
      {{-0x1.73add6605274p+2, 0x1.5d7015e23eeddp+4}, {0x1.147df4dfaa487p+2, 0x1.4eb6fa97dc112p+1}, 0x0p+0, 0x1.5d7987179433p-4},
      {{-0x1.7722bf473a3fp+2, 0x1.8f6b353a81895p+4}, {-0x1.7c878dd077de6p+3, 0x1.18caabb45ec7ap+3}, 0x0p+0, 0x1.11a7d07a67ca9p-1},
      {{-0x1.4bbdd4299f688p+2, 0x1.82fe3987e87c3p+4}, {-0x1.fba334ad4f8b6p+1, -0x1.17a3bdeacb392p+2}, 0x0p+0, 0x1.631dc2e813fadp-1},
      {{-0x1.a1ba596f20975p+2, 0x1.67957ffc9476dp+4}, {0x1.aa8e42e5f39c8p+1, 0x1.d0e5eb450b40fp+2}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.34d8451fab3aap+2, 0x1.ab692c45c35aep+4}, {-0x1.ccbe3b37a9fccp+2, -0x1.80e4233ececd6p+3}, 0x1.4cc7ef63fefe7p-5, 0x1.19799812dea11p-40}},
     {{0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, 8, {-0x1.ae3db673d5e45p-1, 0x1.bcf7e30ff8b08p+2}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, 2, {-0x1.ccf8a3f4b2d67p+2, 0x1.09b567438381cp+1}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, 9, {-0x1.65e1fa6338c48p+2, -0x1.bce10796b102ap+2}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},
    {StepMode::Hybrid, {0x1.48944b9ec3f4p-1, 0x1.9a4a0f3610238p+2}, 0x1.212bf864fc533p+0, 0x1.bc49cc25a27a4p+1, 0x1.021c9ae17398fp-1, 0x1.2fd24616661e4p+1, -0x1.39eb851eb851fp+3,
     {0x1.29eb0cc698f61p-3, 0x1.806f0c4138f5fp-3, 0x1.064e51d018fa3p-3, 0x1.66b40507ba75ap-1},
     {{{0x1.3f2e981cb5fe2p+0, 0x1.9c3c693b3b845p+2}, {-0x1.a8fb28ee17612p+2, -0x1.cb2dd4e5e2a81p+1}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.3d3f4ba4cf531p+0, 0x1.aaf53e0e37f5dp+2}, {0x1.41939c1f8e0a3p+2, -0x1.0565146d82188p+3}, 0x0p+0, 0x1.19799812dea11p-40},
      {{-0x1.1136df3cbcf08p+0, 0x1.5551ecddc3b3cp+2}, {-0x1.8e23a406f3a34p+1, -0x1.8a4aa1749077fp+2}, 0x0p+0, 0x1.19799812dea11p-40},
      {{0x1.f398ed816e035p-1, 0x1.962db9e792159p+2}, {-0x1.0622760368f03p+1, 0x1.e42127a18764ap-5}, 0x0p+0, 0x1.215091858a58bp-8},
      {{-0x1.13e748c631d43p+0, 0x1.53c776065a68ep+2}, {0x1.4777fea3738a3p+3, -0x1.6d64316150d8dp+1}, 0x0p+0, 0x1.74f8e1e8dfdbp-1},
      {{-0x1.c063d80bfcbdp-2, 0x1.68e91ca71e83fp+2}, {-0x1.85bdf0f2709e5p+1, -0x1.94df5bb4a946ap-1}, 0x0p+0, 0x1.9ce67fbd7b749p-4}},
     {{0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, 0, {-0x1.52cc26245789cp+2, 0x1.662ddb80a772fp+2}},
      {0x1.1111111111111p-6, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}},
      {0x1.1111111111111p-5, -1, {0x0p+0, 0x0p+0}},
      {0x1.999999999999ap-4, 5, {0x1.01cfa81b346c2p+2, 0x1.0e5006b1d37dp+3}},
      {0x1.999999999999ap-4, -1, {0x0p+0, 0x0p+0}},
      {0x1p+0, -1, {0x0p+0, 0x0p+0}}}},

};

}  // namespace

TEST(PointsInBoxesOfWalls, NoPointLeavesATurnedBoxOfFourPolygons) {
  for (size_t i = 0; i < std::size(kBoxes); ++i) {
    const WalledBox& box = kBoxes[i];
    SCOPED_TRACE("box " + std::to_string(i));
    World w(container_search::searchWorld(box.mode, box.gravity));
    const Vec2 ux{std::cos(box.angle), std::sin(box.angle)}, uy{-std::sin(box.angle), std::cos(box.angle)};
    auto at = [&](double x, double y) { return box.centre + ux * x + uy * y; };
    const double hw = box.halfWidth, hh = box.halfHeight, t = box.thickness;
    const double walls[4][4] = {{-hw - t, -hh - t, hw + t, -hh}, {-hw - t, hh, hw + t, hh + t}, {-hw - t, -hh, -hw, hh},
                                {hw, -hh, hw + t, hh}};
    const BodyId wallBody = w.createBody({.type = BodyType::Static});
    for (int k = 0; k < 4; ++k) {
      const double* r = walls[k];
      w.createFixture(wallBody, {.geometry = Polygon{{at(r[0], r[1]), at(r[2], r[1]), at(r[2], r[3]), at(r[0], r[3])}},
                                 .restitution = box.wallRestitution[k]});
    }
    const std::vector<Vec2> inner{at(-hw, -hh), at(hw, -hh), at(hw, hh), at(-hw, hh)};
    const std::vector<BodyId> bodies = container_search::throwBodies(w, box.bodies);
    for (size_t s = 0; s < box.steps.size(); ++s) {
      container_search::play(w, bodies, box.steps[s]);
      ASSERT_FALSE(w.stats().eventBudgetReached) << "step " << s;
      for (size_t j = 0; j < bodies.size(); ++j) {
        ASSERT_LE(container_search::distanceOutside(inner, w.position(bodies[j])), 1e-9) << "body " << j << ", step " << s;
      }
    }
  }
}
