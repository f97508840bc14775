// Stream compaction by prefix sums (map_compact_*.comp), mirrored by maintenance_cpu.hpp.
//
// The flags of the visited surfels [active_begin, surfel_count) (map_state.glsl) are scanned in
// tiles of kCompactTileSize (map_compact_scan: a workgroup scans one tile, writing tile-local
// exclusive offsets and the tile's total). The tile totals form level 1, scanned the same way, and
// so on until a level fits one tile (at most 3 levels for 2^26 surfels with 1024-element tiles).
// Add-back passes then make each level's offsets global, top down (map_compact_add); the scatter
// adds level 1 to level 0 on the fly (map_compact_scatter). Two chains are scanned alike: the keep
// flags (surfels staying in the active range) and the retire flags (surfels joining the inactive
// prefix). Every level has at least one tile, so the last level always writes the total, even
// for an empty range.
#ifndef VIFUSION_MAP_COMPACT_GLSL
#define VIFUSION_MAP_COMPACT_GLSL

// Elements per tile: set by the host (spec constant 3) to 4 × the scan's workgroup size.
layout(constant_id = 3) const uint kCompactTileSize = 1024;

uint compactTiles(uint n) { return max(1u, (n + kCompactTileSize - 1u) / kCompactTileSize); }

// Elements of scan level `level` when `visited` surfels were flagged (level 0 = the flags).
uint compactLevelCount(uint visited, uint level) {
  uint n = visited;
  for (uint k = 0u; k < level; ++k) n = compactTiles(n);
  return n;
}

#endif
