-- SPDX-License-Identifier: MIT
-- orb_feat_pkg: layout of the feature stream word (m_axis_feat_tdata, 320 bits).
--   feature beat (tlast = 0): [11:0] score, [23:12] x, [35:24] y (in the scale's pixels),
--                             [37:36] scale, [38] 0, [39] 0, [45:40] orientation sector,
--                             [63:46] 0, [319:64] descriptor (bit 64 + i = test i)
--                             (sector and descriptor 0 when the merge carries no descriptors)
--   end-of-frame beat (tlast = 1): [15:0] frame number (mod 2^16), [31:16] features of that frame
--                             lost to a full FIFO (saturating), [38:32] 0, [39] 1, [319:40] 0

library ieee;
use ieee.std_logic_1164.all;

package orb_feat_pkg is

  constant FEAT_BITS_c        : positive := 320;
  constant FEAT_SCORE_LO_c    : natural  := 0;
  constant FEAT_X_LO_c        : natural  := 12;
  constant FEAT_Y_LO_c        : natural  := 24;
  constant FEAT_SCALE_LO_c    : natural  := 36;
  constant FEAT_EOF_BIT_c     : natural  := 39;
  constant FEAT_SECTOR_LO_c   : natural  := 40;
  constant FEAT_SECTOR_BITS_c : positive := 6;
  constant FEAT_DESC_LO_c     : natural  := 64;
  constant DESC_BITS_c        : positive := 256;
  constant EOF_FRAME_LO_c     : natural  := 0;
  constant EOF_DROPS_LO_c     : natural  := 16;

end package orb_feat_pkg;
