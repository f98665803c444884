// SPDX-License-Identifier: GPL-3.0-or-later
// Issue 30: emotions are a value type, canonical by construction. The modulator compared "happy_for" and
// "fears_confirmed" with canonical labels spelt with '-', so those emotions never got their blink rate and
// head-motion factor; with Emotion::in a misspelt label throws where it is reached.
#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>

#include "base/error.h"
#include "phonetics/emotion.h"
#include "synth/modulator.h"
#include "test_support.h"

using namespace talkhead;
using talkhead::test::errorOf;

TEST(Emotion, canonicalByConstruction) {
	EXPECT_TRUE(Emotion().isNeutral());
	EXPECT_EQ(Emotion().label(), "neutral");
	EXPECT_EQ(Emotion::parse("Sadness"), Emotion::of("distress"));
	EXPECT_EQ(Emotion::parse(" happy_for "), Emotion::of("happy-for"));
	EXPECT_EQ(Emotion::parse("happyfor").label(), "happy-for");
	EXPECT_EQ(Emotion::of("anger").valence(), '-');
	EXPECT_EQ(Emotion::count(), 23u);
	EXPECT_EQ(Emotion::at(1).label(), "joy");
	EXPECT_FALSE(Emotion::find("glee"));
	EXPECT_EQ(errorOf([] { Emotion::parse("glee"); }).rfind("unknown emotion 'glee' (known: neutral, joy, distress, happy-for, ", 0), 0u);
	// Labels written in code must be canonical: neither an alias nor the underscore spelling.
	EXPECT_THROW(Emotion::of("happy_for"), std::logic_error);
	EXPECT_THROW(Emotion::of("sadness"), std::logic_error);
	EXPECT_THROW(Emotion::of("joy").in({"joy", "fears_confirmed"}), std::logic_error);  // every label checked
	EXPECT_TRUE(Emotion::of("pity").in({"joy", "pity"}));
}

TEST(Emotion, everyEmotionGetsItsBlinkRateAndHeadFactor) {
	// The two that never matched before.
	EXPECT_EQ(ShapeModulator::blinkRateFor(Emotion::parse("fears_confirmed")), 10);
	EXPECT_EQ(ShapeModulator::headFactorFor(Emotion::parse("happy-for")), 1.25);
	EXPECT_EQ(ShapeModulator::blinkRateFor(Emotion::of("distress")), 22);
	EXPECT_EQ(ShapeModulator::headFactorFor(Emotion::of("fear")), 0.6);
	EXPECT_EQ(ShapeModulator::blinkRateFor(Emotion()), 17);
	EXPECT_EQ(ShapeModulator::headFactorFor(Emotion()), 1.0);
	// Every label the tables name is reached (a misspelt one would throw here).
	for (std::size_t i = 0; i < Emotion::count(); ++i) {
		EXPECT_NO_THROW(ShapeModulator::blinkRateFor(Emotion::at(i))) << Emotion::at(i).label();
		EXPECT_NO_THROW(ShapeModulator::headFactorFor(Emotion::at(i))) << Emotion::at(i).label();
	}
}

TEST(Expression, checkedOnceWhereItIsMade) {
	const Expression e = Expression::parse("Happy:0.5");  // an alias, any case
	EXPECT_EQ(e.emotion(), Emotion::of("joy"));
	EXPECT_DOUBLE_EQ(e.intensity(), 0.5);
	EXPECT_EQ(e.str(), "joy:0.5");
	EXPECT_EQ(Expression::parse("anger").str(), "anger");
	EXPECT_TRUE(Expression::parse("fear:1.5").extrapolated());
	EXPECT_EQ(Expression(), Expression(Emotion(), 1));
	auto field = [](const std::function<void()>& f) -> std::string {
		try {
			f();
		} catch (const FieldError& e) {
			return e.field() + ": " + e.what();
		}
		return "";
	};
	EXPECT_EQ(field([] { Expression::parse("joy:1.6"); }), "intensity: intensity '1.6' is not a number from 0 to 1.5");
	EXPECT_EQ(field([] { Expression::parse("joy:x"); }), "intensity: intensity 'x' is not a number from 0 to 1.5");
	EXPECT_EQ(field([] { Expression(Emotion::of("joy"), -0.1); }), "intensity: intensity '-0.1' is not a number from 0 to 1.5");
	EXPECT_EQ(field([] { Expression::parse("glee"); }).rfind("emotion: unknown emotion 'glee' (known: neutral, joy,", 0), 0u);
}
