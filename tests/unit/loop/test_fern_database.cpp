// Randomised-fern place recognition: options, block-mean downsampling, seeded fern tests, encoding,
// the dissimilarity's definition, the keyframe rule, queries that exclude recent keyframes, the full-database
// policy and the per-frame path's heap use. Frames are synthesised (boxes of colour and depth), so the test
// needs neither OpenCV nor data files.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "vifusion/loop/fern_database.hpp"
#include "vifusion/loop/fern_encoder.hpp"
#include "vifusion/loop/fern_image.hpp"
#include "vifusion/loop/fern_options.hpp"
#include "vifusion/test/box_scene.hpp"
#include "vifusion/test/counting_allocations.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::loop {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;

RgbdFrame makeScene(std::uint32_t seed, int width = kWidth, int height = kHeight) {
  return test::makeBoxScene(seed, width, height);
}

using test::noisyCopy;

FernCodes codesOf(std::initializer_list<int> values) {
  FernCodes codes(static_cast<int>(values.size()));
  int f = 0;
  for (const int v : values) codes.set(f++, v < 0 ? kInvalidFernCode : static_cast<std::uint8_t>(v));
  return codes;
}

// ---------------------------------------------------------------------------------------------------------------
// Options

TEST(FernOptions, DefaultsAreValid) { EXPECT_NO_THROW(FernOptions{}.validate()); }

TEST(FernOptions, ValidationNamesTheField) {
  const auto expectBad = [](auto mutate, const char* field) {
    FernOptions options;
    mutate(options);
    test::expectError([&] { options.validate(); }, std::string("'") + field + "'");
  };
  expectBad([](FernOptions& o) { o.num_ferns = 0; }, "num_ferns");
  expectBad([](FernOptions& o) { o.num_ferns = 70000; }, "num_ferns");
  expectBad([](FernOptions& o) { o.downsample_factor = 0; }, "downsample_factor");
  expectBad([](FernOptions& o) { o.min_depth_m = 0.0f; }, "min_depth_m");
  expectBad([](FernOptions& o) { o.max_depth_m = 0.3f; }, "max_depth_m");
  expectBad([](FernOptions& o) { o.keyframe_threshold = 1.0; }, "keyframe_threshold");
  expectBad([](FernOptions& o) { o.keyframe_threshold = -0.1; }, "keyframe_threshold");
  expectBad([](FernOptions& o) { o.min_valid_fraction = 0.0; }, "min_valid_fraction");
  expectBad([](FernOptions& o) { o.capacity = 0; }, "capacity");
}

TEST(FernDatabase, RejectsInputNotDivisibleByTheFactor) {
  test::expectError([] { FernDatabase db(FernOptions{}, 644, 480); }, "downsample_factor");
  test::expectError([] { FernDatabase db(FernOptions{}, 640, 0); }, "height");
  FernOptions bad;
  bad.capacity = -1;
  test::expectError([&] { FernDatabase db(bad, 640, 480); }, "'capacity'");
}

// ---------------------------------------------------------------------------------------------------------------
// Downsampling

TEST(FernImage, BlockMeanByHand) {
  // 4×2 input, factor 2 → 2×1. Depth in mm (scale 0.001), max depth 4 m.
  Image<Rgb8> rgb(4, 2);
  Image<std::uint16_t> depth(4, 2);
  // Block (0, 0): pixels (0,0) (1,0) (0,1) (1,1).
  rgb(0, 0) = {10, 1, 255};
  rgb(1, 0) = {20, 2, 255};
  rgb(0, 1) = {30, 2, 254};
  rgb(1, 1) = {41, 2, 254};
  depth(0, 0) = 1000;
  depth(1, 0) = 2000;
  depth(0, 1) = 0;  // missing: not averaged
  depth(1, 1) = 3000;
  // Block (1, 0): exactly half valid (valid), one beyond max depth (missing).
  rgb(2, 0) = {0, 0, 0};
  rgb(3, 0) = {0, 0, 0};
  rgb(2, 1) = {1, 0, 0};
  rgb(3, 1) = {1, 0, 0};
  depth(2, 0) = 1500;
  depth(3, 0) = 0;
  depth(2, 1) = 4500;  // > 4 m
  depth(3, 1) = 2500;

  FernImage out(2, 1);
  downsampleForFerns(rgb.view(), depth.view(), 0.001, 2, 4.0f, out);
  // R: (10+20+30+41)/4 = 25.25 → 25; G: 7/4 = 1.75 → 2; B: 1018/4 = 254.5 → 255 (half rounds up).
  EXPECT_EQ(out.rgb(0, 0), (Rgb8{25, 2, 255}));
  EXPECT_FLOAT_EQ(out.depth_m(0, 0), 2.0f);   // (1 + 2 + 3) / 3
  EXPECT_EQ(out.rgb(1, 0), (Rgb8{1, 0, 0}));  // 2/4 = 0.5 → 1
  EXPECT_FLOAT_EQ(out.depth_m(1, 0), 2.0f);   // (1.5 + 2.5) / 2, two of four valid

  // One valid pixel of four: fewer than half, invalid.
  depth(3, 1) = 0;
  downsampleForFerns(rgb.view(), depth.view(), 0.001, 2, 4.0f, out);
  EXPECT_EQ(out.depth_m(1, 0), 0.0f);
}

TEST(FernImage, AnySizeDivisibleByTheFactor) {
  const RgbdFrame frame = makeScene(3, 96, 36);
  FernImage out(8, 3);
  downsampleForFerns(frame, 12, 4.0f, out);
  // Spot-check one block against a direct mean.
  int sum_r = 0;
  for (int y = 12; y < 24; ++y)
    for (int x = 60; x < 72; ++x) sum_r += frame.rgb(x, y).r;
  EXPECT_EQ(out.rgb(5, 1).r, (sum_r + 72) / 144);
}

TEST(FernImage, SizeMismatchIsAnError) {
  const RgbdFrame frame = makeScene(3, 64, 48);
  FernImage wrong(7, 6);
  test::expectError([&] { downsampleForFerns(frame, 8, 4.0f, wrong); }, "must be 8×6");
  FernImage right(8, 6);
  test::expectError([&] { downsampleForFerns(frame, 7, 4.0f, right); }, "multiple of the factor 7");
}

// ---------------------------------------------------------------------------------------------------------------
// Fern tests and encoding

TEST(SplitMix64, MatchesTheReferenceSequence) {
  // Vigna's splitmix64.c, seed 1234567.
  SplitMix64 rng(1234567);
  EXPECT_EQ(rng.next(), 6457827717110365317ull);
  EXPECT_EQ(rng.next(), 3203168211198807973ull);
  EXPECT_EQ(rng.next(), 9817491932198370423ull);
  EXPECT_EQ(rng.next(), 4593380528125082431ull);
  EXPECT_EQ(rng.next(), 16408922859458223821ull);
}

TEST(FernEncoder, TestsLieInTheirRanges) {
  FernOptions options;
  const FernEncoder encoder(options, 80, 60);
  ASSERT_EQ(encoder.numFerns(), 500);
  int x_max = 0, y_max = 0;
  for (const Fern& fern : encoder.ferns()) {
    EXPECT_GE(fern.x, 0);
    EXPECT_LT(fern.x, 80);
    EXPECT_GE(fern.y, 0);
    EXPECT_LT(fern.y, 60);
    EXPECT_GE(fern.depth_m_threshold, options.min_depth_m);
    EXPECT_LE(fern.depth_m_threshold, options.max_depth_m);
    x_max = std::max(x_max, fern.x);
    y_max = std::max(y_max, fern.y);
  }
  EXPECT_GT(x_max, 70);  // spread over the image, not bunched in a corner
  EXPECT_GT(y_max, 50);
}

TEST(FernEncoder, SameSeedSameCodesDifferentSeedDifferentTests) {
  FernOptions options;
  options.seed = 42;
  FernDatabase a(options, kWidth, kHeight);
  FernDatabase b(options, kWidth, kHeight);
  options.seed = 43;
  FernDatabase c(options, kWidth, kHeight);
  EXPECT_EQ(a.encoder().ferns(), b.encoder().ferns());
  EXPECT_NE(a.encoder().ferns(), c.encoder().ferns());

  const RgbdFrame frame = makeScene(7);
  FernFrame fa = a.makeFrame(), fb = b.makeFrame(), fc = c.makeFrame();
  a.encode(frame, fa);
  b.encode(frame, fb);
  c.encode(frame, fc);
  EXPECT_EQ(fa.codes, fb.codes);
  EXPECT_NE(fa.codes, fc.codes);
}

TEST(FernEncoder, SeedZeroIsPinned) {
  // The first fern of the default seed at 80×60 with the default depth range: a saved database relies on
  // these never changing.
  const FernEncoder encoder(FernOptions{}, 80, 60);
  SplitMix64 rng(0);
  const Fern& first = encoder.ferns().front();
  EXPECT_EQ(first.x, static_cast<int>(rng.uniformBelow(80)));
  EXPECT_EQ(first.y, static_cast<int>(rng.uniformBelow(60)));
  EXPECT_EQ(first.red, rng.uniformBelow(256));
  EXPECT_EQ(first.green, rng.uniformBelow(256));
  EXPECT_EQ(first.blue, rng.uniformBelow(256));
  EXPECT_EQ(first.depth_m_threshold, static_cast<float>(0.4 + rng.uniformUnit() * (4.0 - 0.4)));
  SplitMix64 raw(0);
  EXPECT_EQ(raw.next(), 0xE220A8397B1DCDAFull);  // splitmix64's first output for seed 0
}

TEST(FernEncoder, CodeBitsFollowTheTests) {
  const FernEncoder encoder(FernOptions{}, 80, 60);
  const RgbdFrame frame = makeScene(11);
  FernImage image(80, 60);
  downsampleForFerns(frame, 8, 4.0f, image);
  FernCodes codes(encoder.numFerns());
  encoder.encode(image, codes);
  for (int f = 0; f < encoder.numFerns(); ++f) {
    const Fern& fern = encoder.ferns()[static_cast<std::size_t>(f)];
    const Rgb8 c = image.rgb(fern.x, fern.y);
    const float d = image.depth_m(fern.x, fern.y);
    if (d <= 0.0f) {
      EXPECT_FALSE(codes.isValid(f));
      continue;
    }
    const int expected =
        (c.r > fern.red) + 2 * (c.g > fern.green) + 4 * (c.b > fern.blue) + 8 * (d > fern.depth_m_threshold);
    EXPECT_EQ(codes.code(f), expected) << "fern " << f;
  }
}

TEST(FernEncoder, InvalidDepthGivesInvalidCodes) {
  FernDatabase db(FernOptions{}, kWidth, kHeight);
  RgbdFrame frame = makeScene(5);
  // No depth in the left half of the image, i.e. in downsampled columns < 40.
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth / 2; ++x) frame.depth(x, y) = 0;
  FernFrame encoded = db.makeFrame();
  db.encode(frame, encoded);
  int expected_valid = 0;
  for (int f = 0; f < db.encoder().numFerns(); ++f) {
    const bool left = db.encoder().ferns()[static_cast<std::size_t>(f)].x < 40;
    EXPECT_EQ(encoded.codes.isValid(f), !left) << "fern " << f;
    expected_valid += !left;
  }
  EXPECT_EQ(encoded.codes.validCount(), expected_valid);
  EXPECT_GT(expected_valid, 150);
  EXPECT_LT(expected_valid, 350);
}

// ---------------------------------------------------------------------------------------------------------------
// Dissimilarity

TEST(FernDissimilarity, Definition) {
  // n = min(valid counts), co = valid and equal; D = (n − co) / n.
  EXPECT_EQ(fernDissimilarity(codesOf({1, 2, 3, 4}), codesOf({1, 2, 3, 4})), 0.0);
  EXPECT_EQ(fernDissimilarity(codesOf({1, 2, 3, 4}), codesOf({1, 2, 3, 5})), 0.25);
  // A fern invalid in one frame does not count against the pair: n = 3, co = 3.
  EXPECT_EQ(fernDissimilarity(codesOf({1, 2, 3, 4}), codesOf({-1, 2, 3, 4})), 0.0);
  EXPECT_EQ(fernDissimilarity(codesOf({-1, 2, 3, 4}), codesOf({1, 2, 3, 4})), 0.0);
  // n = min(4, 3) = 3, co = 2.
  EXPECT_DOUBLE_EQ(fernDissimilarity(codesOf({1, 2, 3, 4}), codesOf({-1, 2, 3, 7})), 1.0 / 3.0);
  // Invalid in both is not a co-occurrence: n = 2, co = 0.
  EXPECT_EQ(fernDissimilarity(codesOf({-1, -1, 3, 4}), codesOf({-1, -1, 5, 6})), 1.0);
  // Valid where the other is not: n = 2, co = 0.
  EXPECT_EQ(fernDissimilarity(codesOf({1, 2, -1, -1}), codesOf({-1, -1, 3, 4})), 1.0);
  // Nothing to compare.
  EXPECT_EQ(fernDissimilarity(codesOf({-1, -1}), codesOf({1, 2})), 1.0);
  test::expectError([] { fernDissimilarity(codesOf({1}), codesOf({1, 2})); }, "cannot be compared");
}

TEST(FernCodes, SetKeepsTheValidCount) {
  FernCodes codes(3);
  EXPECT_EQ(codes.validCount(), 0);
  codes.set(0, 5);
  codes.set(1, 15);
  EXPECT_EQ(codes.validCount(), 2);
  codes.set(1, 16);  // out of range: stored as invalid
  EXPECT_FALSE(codes.isValid(1));
  EXPECT_EQ(codes.validCount(), 1);
  codes.set(0, 7);
  EXPECT_EQ(codes.validCount(), 1);
}

TEST(FernDissimilarity, NoisyCopyIsCloserThanAnotherScene) {
  FernDatabase db(FernOptions{}, kWidth, kHeight);
  FernFrame a = db.makeFrame(), a_noisy = db.makeFrame(), b = db.makeFrame();
  for (std::uint32_t scene = 0; scene < 5; ++scene) {
    const RgbdFrame frame = makeScene(100 + scene);
    db.encode(frame, a);
    db.encode(noisyCopy(frame, 6, scene), a_noisy);
    db.encode(makeScene(200 + scene), b);
    EXPECT_EQ(fernDissimilarity(a.codes, a.codes), 0.0);
    const double same = fernDissimilarity(a.codes, a_noisy.codes);
    const double other = fernDissimilarity(a.codes, b.codes);
    EXPECT_LT(same, db.options().keyframe_threshold) << "scene " << scene;
    EXPECT_GT(other, db.options().keyframe_threshold) << "scene " << scene;
    EXPECT_LT(same, other);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Database

TEST(FernDatabase, KeyframeRuleAddsNovelAndRefusesNearDuplicates) {
  FernDatabase db(FernOptions{}, kWidth, kHeight);
  FernFrame frame = db.makeFrame();
  const RgbdFrame scene_a = makeScene(1);
  const SE3d T_W_C(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())), Eigen::Vector3d(1, 2, 3));

  db.encode(scene_a, frame);
  FernAddResult r = db.addIfNovel(frame, T_W_C, 1'000, 10);
  EXPECT_EQ(r.outcome, FernAddOutcome::kAdded);
  EXPECT_EQ(r.keyframe, 0);
  EXPECT_EQ(r.min_dissimilarity, 1.0);  // empty database
  ASSERT_EQ(db.size(), 1);

  const FernKeyframe kf = db.keyframe(0);
  EXPECT_TRUE(kf.T_W_C.matrix().isApprox(T_W_C.matrix()));
  EXPECT_EQ(kf.t_ns, 1'000);
  EXPECT_EQ(kf.frame_index, 10u);
  EXPECT_EQ(kf.valid_count, frame.codes.validCount());
  EXPECT_TRUE(std::equal(kf.codes.begin(), kf.codes.end(), frame.codes.data()));
  EXPECT_EQ(kf.rgb.width, 80);
  EXPECT_EQ(kf.depth_m.height, 60);
  EXPECT_EQ(kf.rgb(17, 23), frame.image.rgb(17, 23));
  EXPECT_EQ(kf.depth_m(17, 23), frame.image.depth_m(17, 23));

  db.encode(noisyCopy(scene_a, 6, 9), frame);
  r = db.addIfNovel(frame, T_W_C, 2'000, 11);
  EXPECT_EQ(r.outcome, FernAddOutcome::kSimilar);
  EXPECT_EQ(r.keyframe, 0);
  EXPECT_LE(r.min_dissimilarity, db.options().keyframe_threshold);
  EXPECT_EQ(db.size(), 1);

  db.encode(makeScene(2), frame);
  r = db.addIfNovel(frame, SE3d(), 3'000, 12);
  EXPECT_EQ(r.outcome, FernAddOutcome::kAdded);
  EXPECT_EQ(r.keyframe, 1);
  EXPECT_GT(r.min_dissimilarity, db.options().keyframe_threshold);
  EXPECT_EQ(db.size(), 2);

  // The stored pose can be moved by a deformation.
  db.setPose(1, T_W_C);
  EXPECT_TRUE(db.keyframe(1).T_W_C.matrix().isApprox(T_W_C.matrix()));
  test::expectError([&] { db.keyframe(2); }, "no keyframe 2");
}

TEST(FernDatabase, FramesWithTooLittleDepthAreNeitherAddedNorQueried) {
  FernDatabase db(FernOptions{}, kWidth, kHeight);
  FernFrame frame = db.makeFrame();
  db.encode(makeScene(1), frame);
  ASSERT_TRUE(db.addIfNovel(frame, SE3d(), 0, 0).added());

  RgbdFrame blind = makeScene(1);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      if (x >= 16 || y >= 16) blind.depth(x, y) = 0;  // depth only in the top-left 2×2 blocks
  db.encode(blind, frame);
  ASSERT_LT(frame.codes.validCount(), db.minValidFerns());
  const FernAddResult r = db.addIfNovel(frame, SE3d(), 1, 1);
  EXPECT_EQ(r.outcome, FernAddOutcome::kTooFewValid);
  EXPECT_FALSE(db.nearest(frame.codes).found());
  EXPECT_EQ(db.minValidFerns(), 50);  // 10 % of 500
}

TEST(FernDatabase, IndexAgreesWithTheDefinition) {
  FernOptions options;
  options.num_ferns = 64;
  options.capacity = 200;
  options.keyframe_threshold = 0.0;  // add all distinct frames
  options.min_valid_fraction = 0.25;
  FernDatabase db(options, 16, 8);
  std::mt19937 rng(5);
  const auto randomCodes = [&](FernCodes& codes) {
    for (int f = 0; f < codes.size(); ++f) {
      const std::uint32_t r = rng() % 20;  // 4 in 20 invalid
      codes.set(f, r < kFernCodeCount ? static_cast<std::uint8_t>(r) : kInvalidFernCode);
    }
  };
  FernFrame frame = db.makeFrame();
  std::vector<FernCodes> stored;
  while (db.size() < 150) {
    randomCodes(frame.codes);
    if (db.addIfNovel(frame, SE3d(), 0, static_cast<std::uint32_t>(db.size())).added()) stored.push_back(frame.codes);
  }
  for (int trial = 0; trial < 50; ++trial) {
    FernCodes query(64);
    randomCodes(query);
    if (trial % 5 == 0) query = stored[static_cast<std::size_t>(trial)];  // exact hits too
    const FernMatch match = db.nearest(query);
    ASSERT_TRUE(match.found());
    double best = 2.0;
    int best_id = -1;
    for (std::size_t k = 0; k < stored.size(); ++k) {
      const double d = fernDissimilarity(query, stored[k]);
      if (d < best) best = d, best_id = static_cast<int>(k);
    }
    EXPECT_EQ(match.dissimilarity, best);
    EXPECT_EQ(match.keyframe, best_id);  // ties go to the oldest
  }
}

TEST(FernDatabase, QueryExcludesRecentKeyframes) {
  FernDatabase db(FernOptions{}, kWidth, kHeight);
  FernFrame frame = db.makeFrame();
  const RgbdFrame old_scene = makeScene(21);
  const RgbdFrame new_scene = makeScene(22);
  db.encode(old_scene, frame);
  ASSERT_TRUE(db.addIfNovel(frame, SE3d(), 0, 10).added());
  db.encode(new_scene, frame);
  ASSERT_TRUE(db.addIfNovel(frame, SE3d(), 0, 500).added());

  // Looking at the new place at frame 600: keyframe 1 is only 100 frames old, so with a 300-frame gap the
  // best candidate is the old, dissimilar keyframe 0.
  db.encode(noisyCopy(new_scene, 4, 1), frame);
  FernMatch m = db.query(frame.codes, 600, 300);
  ASSERT_TRUE(m.found());
  EXPECT_EQ(m.keyframe, 0);
  EXPECT_GT(m.dissimilarity, db.options().keyframe_threshold);
  // At frame 800 it is old enough (500 + 300 ≤ 800).
  m = db.query(frame.codes, 800, 300);
  EXPECT_EQ(m.keyframe, 1);
  EXPECT_LT(m.dissimilarity, db.options().keyframe_threshold);
  // Gap 0 sees everything; before frame 310 nothing is old enough (and no unsigned wrap-around).
  EXPECT_EQ(db.query(frame.codes, 600, 0).keyframe, 1);
  EXPECT_FALSE(db.query(frame.codes, 309, 300).found());
  EXPECT_EQ(db.query(frame.codes, 310, 300).keyframe, 0);
  EXPECT_EQ(db.query(frame.codes, 0xFFFFFFFFu, 0xFFFFFFFFu).keyframe, FernMatch::kNone);
}

TEST(FernDatabase, FullDatabaseRefusesAndCounts) {
  FernOptions options;
  options.capacity = 2;
  FernDatabase db(options, kWidth, kHeight);
  FernFrame frame = db.makeFrame();
  for (std::uint32_t scene = 0; scene < 2; ++scene) {
    db.encode(makeScene(300 + scene), frame);
    ASSERT_TRUE(db.addIfNovel(frame, SE3d(), scene, scene).added());
  }
  EXPECT_TRUE(db.full());

  db.encode(makeScene(400), frame);  // novel
  FernAddResult r = db.addIfNovel(frame, SE3d(), 5, 5);
  EXPECT_EQ(r.outcome, FernAddOutcome::kFull);
  EXPECT_GT(r.min_dissimilarity, options.keyframe_threshold);
  EXPECT_EQ(db.fullRefusals(), 1u);
  EXPECT_EQ(db.size(), 2);

  // A near duplicate is "similar", not a capacity refusal.
  db.encode(noisyCopy(makeScene(300), 5, 3), frame);
  r = db.addIfNovel(frame, SE3d(), 6, 6);
  EXPECT_EQ(r.outcome, FernAddOutcome::kSimilar);
  EXPECT_EQ(r.keyframe, 0);
  EXPECT_EQ(db.fullRefusals(), 1u);
  // The old keyframes are kept, unchanged.
  EXPECT_EQ(db.keyframe(0).frame_index, 0u);
  EXPECT_EQ(db.keyframe(1).frame_index, 1u);

  db.reset();
  EXPECT_EQ(db.size(), 0);
  EXPECT_EQ(db.fullRefusals(), 0u);
  EXPECT_FALSE(db.nearest(frame.codes).found());
  EXPECT_TRUE(db.addIfNovel(frame, SE3d(), 7, 7).added());
  EXPECT_EQ(db.nearest(frame.codes).keyframe, 0);
  EXPECT_EQ(db.nearest(frame.codes).dissimilarity, 0.0);
}

TEST(FernDatabase, PerFramePathAllocatesNothing) {
  // Start-up: database, frame buffers, input frames (the ring's memory in the real pipeline).
  FernOptions options;
  options.capacity = 8;
  FernDatabase db(options, kWidth, kHeight);
  FernFrame frame = db.makeFrame();
  std::vector<RgbdFrame> inputs;
  for (std::uint32_t scene = 0; scene < 12; ++scene) inputs.push_back(makeScene(500 + scene));
  inputs.push_back(noisyCopy(inputs[0], 5, 1));

  const std::uint64_t before = test::heapAllocationCount();
  double checksum = 0.0;
  for (std::uint32_t i = 0; i < inputs.size(); ++i) {
    db.encode(inputs[i], frame);
    const FernMatch m = db.query(frame.codes, i * 100, 300);
    checksum += m.dissimilarity;
    const FernAddResult r = db.addIfNovel(frame, SE3d(), i, i * 100);  // adds, similar and full refusals
    checksum += r.min_dissimilarity;
    checksum += db.keyframe(0).depth_m(1, 1);
  }
  EXPECT_EQ(test::heapAllocationCount(), before);
  EXPECT_TRUE(db.full());
  EXPECT_GT(db.fullRefusals(), 0u);
  EXPECT_GT(checksum, 0.0);
  const std::vector<int> probe(3);  // the counter does see allocations
  EXPECT_GT(test::heapAllocationCount(), before);
}

}  // namespace
}  // namespace vifusion::loop
