// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Matrix products that round the same on every machine (issue 44, D74).
//
// Eigen cuts a matrix product into blocks whose sizes it derives from the CPU's cache sizes (read with CPUID
// at first use) and from the number of OpenMP threads; the block sizes decide how each sum is grouped, so
// the same product of the same floats rounded differently on a machine with other caches or other core
// counts (a model, and the frames drawn from it, then differed). pinEigenBlocking() fixes the cache sizes
// Eigen plans with to its own x86 defaults; talkhead builds no Eigen code with OpenMP (products are
// parallelised in fixed chunks: productInRowChunks), so the thread count never enters. Call it before any
// large product; it is cheap and idempotent.
#include <Eigen/Core>

namespace talkhead {

void pinEigenBlocking();

// out = a · b, computed in chunks of a fixed number of rows on `threads` threads (0: all cores); each chunk
// is one Eigen product planned for its own size, so the result does not depend on the thread count.
void productInRowChunks(const Eigen::MatrixXf& a, const Eigen::MatrixXf& b, Eigen::MatrixXf& out, unsigned threads = 0);

}  // namespace talkhead
