-- SPDX-License-Identifier: MIT
-- orb_feat_merge: merges the feature streams of SCALES_g scales into one AXI4-Stream. Each scale
-- has a FIFO of FIFO_DEPTH_g entries; a round-robin arbiter moves one feature per clock to the
-- output register. When every scale has finished a frame (its frame_done marker is at the head of
-- its FIFO), one end-of-frame beat (tlast = 1, layout in orb_feat_pkg) follows that frame's
-- features. A feature that finds its FIFO full is dropped and counted (per frame in the
-- end-of-frame beat, in total on `dropped`); frame markers are never dropped.

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_feat_pkg.all;

entity orb_feat_merge is
  generic (
    SCALES_g     : positive range 1 to 4   := 1;
    FIFO_DEPTH_g : positive range 2 to 512 := 32
  );
  port (
    clk                : in    std_logic;
    rst                : in    std_logic;
    in_valid           : in    std_logic_vector(SCALES_g - 1 downto 0);
    in_x               : in    std_logic_vector(SCALES_g * COORD_BITS_c - 1 downto 0);
    in_y               : in    std_logic_vector(SCALES_g * COORD_BITS_c - 1 downto 0);
    in_score           : in    std_logic_vector(SCALES_g * SCORE_BITS_c - 1 downto 0);
    in_done            : in    std_logic_vector(SCALES_g - 1 downto 0);
    m_axis_feat_tdata  : out   std_logic_vector(FEAT_BITS_c - 1 downto 0);
    m_axis_feat_tvalid : out   std_logic;
    m_axis_feat_tready : in    std_logic;
    m_axis_feat_tlast  : out   std_logic;
    dropped            : out   std_logic_vector(31 downto 0)
  );
end entity orb_feat_merge;

architecture rtl of orb_feat_merge is

  -- FIFO entry: marker flag, y, x, score
  constant ENTRY_BITS_c : positive := 1 + 2 * COORD_BITS_c + SCORE_BITS_c;
  constant PTR_BITS_c   : positive := clog2(FIFO_DEPTH_g);

  type fifo_mem_t is array (0 to FIFO_DEPTH_g - 1) of std_logic_vector(ENTRY_BITS_c - 1 downto 0);
  type fifo_arr_t is array (0 to SCALES_g - 1) of fifo_mem_t;
  type ptr_arr_t is array (0 to SCALES_g - 1) of natural range 0 to FIFO_DEPTH_g - 1;
  type cnt_arr_t is array (0 to SCALES_g - 1) of natural range 0 to FIFO_DEPTH_g;

  signal fifo      : fifo_arr_t;
  signal head      : ptr_arr_t := (others => 0);
  signal tail      : ptr_arr_t := (others => 0);
  signal count     : cnt_arr_t := (others => 0);
  signal pend_done : std_logic_vector(SCALES_g - 1 downto 0) := (others => '0');
  signal rr        : natural range 0 to SCALES_g - 1 := 0;
  signal o_valid   : std_logic := '0';
  signal o_last    : std_logic := '0';
  signal o_data    : std_logic_vector(FEAT_BITS_c - 1 downto 0) := (others => '0');
  signal frame_no  : unsigned(15 downto 0) := (others => '0');
  signal frame_drp : unsigned(15 downto 0) := (others => '0');
  signal total_drp : unsigned(31 downto 0) := (others => '0');

begin

  assert FIFO_DEPTH_g = 2 ** PTR_BITS_c
    report "orb_feat_merge: FIFO_DEPTH_g must be a power of two"
    severity failure;

  merge : process (clk) is
    variable entry     : std_logic_vector(ENTRY_BITS_c - 1 downto 0);
    variable is_marker : boolean;
    variable pop       : integer range -1 to SCALES_g - 1;
    variable pop_all   : boolean;
    variable all_mark  : boolean;
    variable s         : natural range 0 to SCALES_g - 1;
    variable cnt       : cnt_arr_t;
    variable hd, tl    : ptr_arr_t;
    variable pend      : std_logic_vector(SCALES_g - 1 downto 0);
    variable drops     : natural range 0 to SCALES_g;
    variable fdrp      : unsigned(15 downto 0);
  begin
    if rising_edge(clk) then
      cnt   := count;
      hd    := head;
      tl    := tail;
      pend  := pend_done;
      drops := 0;
      fdrp  := frame_drp;

      -- output side: choose what to load into the output register
      if o_valid = '0' or m_axis_feat_tready = '1' then
        o_valid  <= '0';
        o_last   <= '0';
        pop      := -1;
        all_mark := true;
        for k in 0 to SCALES_g - 1 loop
          if cnt(k) = 0 or fifo(k)(hd(k))(ENTRY_BITS_c - 1) = '0' then
            all_mark := false;
          end if;
        end loop;
        for k in 0 to SCALES_g - 1 loop
          s := (rr + k) mod SCALES_g;
          if pop < 0 and cnt(s) > 0 and fifo(s)(hd(s))(ENTRY_BITS_c - 1) = '0' then
            pop := s;
          end if;
        end loop;
        if pop >= 0 then
          entry   := fifo(pop)(hd(pop));
          o_valid <= '1';
          o_data  <= (others => '0');
          o_data(FEAT_SCORE_LO_c + SCORE_BITS_c - 1 downto FEAT_SCORE_LO_c) <= entry(SCORE_BITS_c - 1 downto 0);
          o_data(FEAT_X_LO_c + COORD_BITS_c - 1 downto FEAT_X_LO_c) <=
            entry(SCORE_BITS_c + COORD_BITS_c - 1 downto SCORE_BITS_c);
          o_data(FEAT_Y_LO_c + COORD_BITS_c - 1 downto FEAT_Y_LO_c) <=
            entry(SCORE_BITS_c + 2 * COORD_BITS_c - 1 downto SCORE_BITS_c + COORD_BITS_c);
          o_data(FEAT_SCALE_LO_c + 1 downto FEAT_SCALE_LO_c) <= std_logic_vector(to_unsigned(pop, 2));
          hd(pop)  := (hd(pop) + 1) mod FIFO_DEPTH_g;
          cnt(pop) := cnt(pop) - 1;
          rr       <= (pop + 1) mod SCALES_g;
        elsif all_mark then
          o_valid <= '1';
          o_last  <= '1';
          o_data  <= (others => '0');
          o_data(FEAT_EOF_BIT_c) <= '1';
          o_data(EOF_FRAME_LO_c + 15 downto EOF_FRAME_LO_c) <= std_logic_vector(frame_no);
          o_data(EOF_DROPS_LO_c + 15 downto EOF_DROPS_LO_c) <= std_logic_vector(frame_drp);
          frame_no <= frame_no + 1;
          fdrp     := (others => '0');
          for k in 0 to SCALES_g - 1 loop
            hd(k)  := (hd(k) + 1) mod FIFO_DEPTH_g;
            cnt(k) := cnt(k) - 1;
          end loop;
        end if;
      end if;

      -- input side: push features and frame markers (a marker waits in pend_done while full)
      for k in 0 to SCALES_g - 1 loop
        pend(k) := pend(k) or in_done(k);
        if in_valid(k) = '1' then
          if cnt(k) < FIFO_DEPTH_g then
            fifo(k)(tl(k)) <= '0' & in_y((k + 1) * COORD_BITS_c - 1 downto k * COORD_BITS_c) &
                              in_x((k + 1) * COORD_BITS_c - 1 downto k * COORD_BITS_c) &
                              in_score((k + 1) * SCORE_BITS_c - 1 downto k * SCORE_BITS_c);
            tl(k)  := (tl(k) + 1) mod FIFO_DEPTH_g;
            cnt(k) := cnt(k) + 1;
          else
            drops := drops + 1;
          end if;
        elsif pend(k) = '1' and cnt(k) < FIFO_DEPTH_g then
          fifo(k)(tl(k)) <= (ENTRY_BITS_c - 1 => '1', others => '0');
          tl(k)   := (tl(k) + 1) mod FIFO_DEPTH_g;
          cnt(k)  := cnt(k) + 1;
          pend(k) := '0';
        end if;
      end loop;
      if drops > 0 then
        total_drp <= total_drp + drops;
        if fdrp < 2 ** 16 - SCALES_g then
          fdrp := fdrp + drops;
        end if;
      end if;
      frame_drp <= fdrp;

      count     <= cnt;
      head      <= hd;
      tail      <= tl;
      pend_done <= pend;

      if rst = '1' then
        count     <= (others => 0);
        head      <= (others => 0);
        tail      <= (others => 0);
        pend_done <= (others => '0');
        rr        <= 0;
        o_valid   <= '0';
        o_last    <= '0';
        frame_no  <= (others => '0');
        frame_drp <= (others => '0');
        total_drp <= (others => '0');
      end if;
    end if;
  end process merge;

  m_axis_feat_tdata  <= o_data;
  m_axis_feat_tvalid <= o_valid;
  m_axis_feat_tlast  <= o_last;
  dropped            <= std_logic_vector(total_drp);

end architecture rtl;
