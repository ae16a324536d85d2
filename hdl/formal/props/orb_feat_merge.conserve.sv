// SPDX-License-Identifier: MIT
// orb_feat_merge.conserve: `no_invention` (never more out than in).
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  `include "orb_feat_merge.counts.svh"
  // nothing out that did not go in: never more features out (and counted lost) than in; never more
  // end-of-frame beats than frame ends of any scale
  always @(*) if (!init && !rst)
    no_invention: assert (!inside[7] && e_out <= d0 && e_out <= d1);
