-- SPDX-License-Identifier: MIT
-- orb_slot_pkg: the 64-byte slot the CPU reads, made from a beat of the feature stream, shared by
-- the two feature memories (orb_feat_mem's banks in block RAM, orb_feat_dma's ring in DDR) so that
-- both write the same slot bit for bit. slot_word returns CPU words 0 .. SLOT_WORDS_USED_c - 1 of
-- the slot (word k at bits 32 * k + 31 downto 32 * k; words 10 .. 15 are 0 and not returned), at
-- orb_feat_pkg's SLOT_/REC_ positions (docs/feature-word.md): for a feature beat its x, y, score,
-- response, scale, low flag, sector and descriptor (record flag 0); for the end-of-frame beat the
-- record: the frame's feature count and truncated count (given), the truncated flag, and the frame
-- number, dropped count and parameters the beat carries. A field of the stream word is copied whole
-- (its orb_feat_pkg width), the rest of its slot field stays 0. Combinational.
-- Docs: docs/feature-memory.md, docs/feature-dma.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_feat_pkg.all;

package orb_slot_pkg is

  constant SLOT_DATA_BITS_c : positive := 32 * SLOT_WORDS_USED_c;

  -- data: a beat of the feature stream; last: it is the end-of-frame beat; count, trunc: the
  -- frame's stored and truncated features (only used for the end-of-frame record)
  function slot_word (
    data  : std_logic_vector(FEAT_BITS_c - 1 downto 0);
    last  : std_logic;
    count : unsigned;
    trunc : unsigned(31 downto 0)
  ) return std_logic_vector;

end package orb_slot_pkg;

package body orb_slot_pkg is

  function slot_word (
    data  : std_logic_vector(FEAT_BITS_c - 1 downto 0);
    last  : std_logic;
    count : unsigned;
    trunc : unsigned(31 downto 0)
  ) return std_logic_vector is
    variable w : std_logic_vector(SLOT_DATA_BITS_c - 1 downto 0);

    -- w(dst + bits - 1 downto dst) := data(src + bits - 1 downto src)
    procedure copy_field (
      dst  : natural;
      src  : natural;
      bits : positive
    ) is
    begin
      w(dst + bits - 1 downto dst) := data(src + bits - 1 downto src);
    end procedure copy_field;

  begin
    w := (others => '0');
    if last = '1' then
      w(REC_COUNT_LO_c + count'length - 1 downto REC_COUNT_LO_c) := std_logic_vector(count);
      w(SLOT_RECORD_BIT_c)                                       := '1';
      if trunc /= 0 then
        w(REC_TRUNCATED_BIT_c) := '1';
      end if;
      copy_field(REC_FRAME_LO_c, EOF_FRAME_LO_c, EOF_FRAME_BITS_c);
      copy_field(REC_DROPPED_LO_c, EOF_DROPS_LO_c, EOF_DROPS_BITS_c);
      w(REC_TRUNC_LO_c + trunc'length - 1 downto REC_TRUNC_LO_c) := std_logic_vector(trunc);
      copy_field(REC_THRESHOLD_LO_c, EOF_THRESHOLD_LO_c, EOF_THRESHOLD_BITS_c);
      copy_field(REC_TLO_LO_c, EOF_TLO_LO_c, EOF_TLO_BITS_c);
      w(REC_MODE_ORB_BIT_c)                                      := data(EOF_MODE_ORB_BIT_c);
      w(REC_SELECT_GRID_BIT_c)                                   := data(EOF_SELECT_GRID_BIT_c);
      copy_field(REC_BUDGET_LO_c, EOF_BUDGET_LO_c, EOF_BUDGET_BITS_c);
      copy_field(REC_COLS_LO_c, EOF_COLS_LO_c, EOF_COLS_BITS_c);
      copy_field(REC_ROWS_LO_c, EOF_ROWS_LO_c, EOF_ROWS_BITS_c);
    else
      copy_field(SLOT_X_LO_c, FEAT_X_LO_c, FEAT_X_BITS_c);
      copy_field(SLOT_Y_LO_c, FEAT_Y_LO_c, FEAT_Y_BITS_c);
      copy_field(SLOT_SCORE_LO_c, FEAT_SCORE_LO_c, FEAT_SCORE_BITS_c);
      copy_field(SLOT_RESPONSE_LO_c, FEAT_RESPONSE_LO_c, FEAT_RESPONSE_BITS_c);
      copy_field(SLOT_SCALE_LO_c, FEAT_SCALE_LO_c, FEAT_SCALE_BITS_c);
      w(SLOT_LOW_BIT_c) := data(FEAT_LOW_BIT_c);
      copy_field(SLOT_SECTOR_LO_c, FEAT_SECTOR_LO_c, FEAT_SECTOR_BITS_c);
      copy_field(SLOT_DESC_LO_c, FEAT_DESC_LO_c, FEAT_DESC_BITS_c);
    end if;
    return w;
  end function slot_word;

end package body orb_slot_pkg;
