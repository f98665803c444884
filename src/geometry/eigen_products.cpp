// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/eigen_products.h"

#include <mutex>

#include "base/parallel.h"

namespace talkhead {

void pinEigenBlocking() {
	static std::once_flag once;
	// Eigen's defaults for x86 when CPUID says nothing (GeneralBlockPanelKernel.h): L1 32 KiB, L2 256 KiB,
	// L3 2 MiB. Smaller than most caches now, which costs little: the blocks still fit.
	std::call_once(once, [] { Eigen::setCpuCacheSizes(32 * 1024, 256 * 1024, 2 * 1024 * 1024); });
}

void productInRowChunks(const Eigen::MatrixXf& a, const Eigen::MatrixXf& b, Eigen::MatrixXf& out, unsigned threads) {
	pinEigenBlocking();
	out.resize(a.rows(), b.cols());
	// A multiple of every packet size; large enough that each chunk is a real GEMM.
	constexpr Eigen::Index rows = 4096;
	const Eigen::Index chunks = (a.rows() + rows - 1) / rows;
	parallelFor(std::size_t(chunks), threads, [&](std::size_t c) {
		const Eigen::Index r0 = Eigen::Index(c) * rows, n = std::min(rows, a.rows() - r0);
		out.middleRows(r0, n).noalias() = a.middleRows(r0, n) * b;
	});
}

}  // namespace talkhead
