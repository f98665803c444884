// A program using the installed talkhead library.
#include <cstdio>

#include "geometry/scheme.h"
#include "geometry/shape.h"

int main() {
	talkhead::Points a(3, 2), b(3, 2);
	a << 0, 0, 1, 0, 0, 1;
	b = talkhead::Similarity::fromScaleAngle(2.0, 0.0, 0, 0).apply(a);
	auto s = talkhead::alignSimilarity(a, b, Eigen::VectorXd::Ones(3));
	std::printf("similarity scale %.0f\n", s.scale());
	std::printf("scheme %s\n", talkhead::loadScheme("imm-73").name.c_str());
	return 0;
}
