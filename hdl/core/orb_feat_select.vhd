-- SPDX-License-Identifier: MIT
-- orb_feat_select: the grid selection of one pyramid level (docs/spec.md section 14,
-- docs/selection.md), decided as the level's candidates stream past, in their arrival order
-- (raster order but for fast mode's last row of centres, which the NMS decides with the row above
-- it: golden_model.select.arrival_order), at most one every second clock. For
-- each candidate it gives one decision: dropped, or stored in slot `out_slot` (0 .. budget - 1) of
-- the level, a slot new in this frame (`out_new`) or one whose occupant it replaces. The kept set
-- after the frame's last candidate is golden_model.select.select_level's, and the decisions are
-- golden_model.select.LevelSelector's, one for one.
--
-- The cells are a grid of `cols` x `rows` cells over the frame, the same at every level: the cell
-- of (x, y) is ((x Kx + Ox) >> 24, (y Ky + Oy) >> 24), the constants of the level (orb_util_pkg's
-- cell_k and cell_o, from the generics) looked up by cols and rows: the cell that holds the
-- candidate's full-resolution position. Ky < 2^24, so a cell row is at least a pixel row high:
-- only the current cell row and the one above it can change (a candidate arrives at most one pixel
-- row above the last), and the cell table holds two rows, one per parity of the cell row: per cell its
-- floor's rest key, rank (main flag and code), slot and a `rejected` flag, valid where its `touched` bit is
-- set; a parity's bits clear when a new row takes it. The rest R is a store of buckets, one per rest
-- key (max(code, 1) for a main candidate, 0 for a low one: a low corner takes only a free place),
-- each a LIFO list of slots through the next-pointer RAM (each entry flags NIL_c beside
-- the pointer). The lowest bucket, the one evictions take from, is kept in registers (its key,
-- its top slot and the slot below it, prefetched from the next-pointer RAM): a pop needs no table
-- write, so no operation writes the bucket heads twice; `upper` marks the other non-empty buckets,
-- so the next one up is upper's lowest set bit, with no compare against the lowest. Pipeline: two
-- clocks for the cell (multiply and add, DSP48), then D1 (reads: cell table, bucket heads, the next
-- non-empty bucket; and the decision's predicates: the rank against the floor's, the keys
-- against the lowest bucket's) and D2 (decision from those registers, writes; the next-pointer
-- RAM's write registered, landing a clock later); a decision leaves
-- FEAT_SELECT_LAT_c = 5 clocks after its candidate (orb_latency_pkg, docs/latency.md). In `all`
-- mode (grid = 0) every main candidate is kept (new), low ones are dropped, and no state changes.
-- The parameters (grid, budget, cols, rows) must hold from the frame's first candidate to in_done;
-- in_done (after the frame's last candidate has left) clears the frame's state.
-- Ports and generics: docs/entities/orb_feat_select.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;
use work.orb_fast_pkg.all;
use work.orb_limits_pkg.all;

entity orb_feat_select is
  generic (
    SLOTS_g : positive range 1 to 4095 := 1023; -- the largest budget the level can be given
    -- the cell map: the frame's size, the pyramid step and the level
    FULL_WIDTH_g  : width_t              := 640;
    FULL_HEIGHT_g : height_t             := 480;
    STEP_NUM_g    : step_num_t           := 2;
    STEP_DEN_g    : step_den_t           := 1;
    LEVEL_g       : natural range 0 to 7 := 0
  );
  port (
    clk : in    std_logic;
    rst : in    std_logic;
    -- the frame's parameters
    grid   : in    std_logic;
    budget : in    std_logic_vector(SEL_SLOT_BITS_c - 1 downto 0);
    cols   : in    std_logic_vector(GRID_BITS_c - 1 downto 0); -- cells across the frame, 1 .. 15
    rows   : in    std_logic_vector(GRID_BITS_c - 1 downto 0); -- cells down the frame, 1 .. 15
    -- candidates
    in_valid : in    std_logic;
    in_x     : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y     : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_low   : in    std_logic;
    in_code  : in    std_logic_vector(RESPONSE_BITS_c - 1 downto 0);
    in_done  : in    std_logic;
    -- decisions
    out_valid : out   std_logic;
    out_keep  : out   std_logic;
    out_slot  : out   std_logic_vector(SEL_SLOT_BITS_c - 1 downto 0);
    out_new   : out   std_logic
  );
end entity orb_feat_select;

architecture rtl of orb_feat_select is

  -- cells in a row, at most
  constant CELLS_c : positive := 2 ** GRID_BITS_c;
  constant CBITS_c : positive := GRID_BITS_c;
  -- the cell map's product and sum: (v K + O) < 2^24 (2^GRID_BITS_c + 1)
  constant MAP_BITS_c : positive := COORD_BITS_c + CELL_SHIFT_c + 1;
  constant BUCKETS_c  : positive := 2 ** RESPONSE_BITS_c;
  -- next-pointer RAM address bits
  constant NBITS_c : positive := clog2(SLOTS_g + 1);
  -- no slot (budget <= 4095)
  constant NIL_c : unsigned(SEL_SLOT_BITS_c - 1 downto 0) := (others => '1');

  subtype slot_t is unsigned(SEL_SLOT_BITS_c - 1 downto 0);
  subtype code_t is unsigned(RESPONSE_BITS_c - 1 downto 0);
  -- main & code
  subtype rank_t is unsigned(RESPONSE_BITS_c downto 0);
  subtype cell_t is unsigned(CBITS_c - 1 downto 0);

  -- the cell map's constants of this level, by cols (rows); 0 for the illegal 0
  subtype map_t is unsigned(CELL_SHIFT_c - 1 downto 0);

  type map_rom_t is array (0 to 2 ** GRID_BITS_c - 1) of map_t;

  function map_rom (full : positive; offset : boolean) return map_rom_t is
    variable r : map_rom_t := (others => (others => '0'));
  begin
    for c in 1 to 2 ** GRID_BITS_c - 1 loop
      if offset then
        r(c) := to_unsigned(cell_o(c, full, STEP_NUM_g, STEP_DEN_g, LEVEL_g), CELL_SHIFT_c);
      else
        r(c) := to_unsigned(cell_k(c, full, STEP_NUM_g, STEP_DEN_g, LEVEL_g), CELL_SHIFT_c);
      end if;
    end loop;
    return r;
  end function map_rom;

  constant KX_ROM_c : map_rom_t := map_rom(FULL_WIDTH_g, false);
  constant OX_ROM_c : map_rom_t := map_rom(FULL_WIDTH_g, true);
  constant KY_ROM_c : map_rom_t := map_rom(FULL_HEIGHT_g, false);
  constant OY_ROM_c : map_rom_t := map_rom(FULL_HEIGHT_g, true);

  -- cell table entry: rejected & rest key & rank & slot
  constant CT_BITS_c : positive := 1 + RESPONSE_BITS_c + RESPONSE_BITS_c + 1 + SEL_SLOT_BITS_c;

  -- the rest's key of a candidate (docs/spec.md section 14): max(code, 1) for a main one, 0 for a low one
  function rest_key (low : std_logic; code : code_t) return code_t is
  begin
    if low = '1' then
      return (others => '0');
    elsif code = 0 then
      return to_unsigned(1, RESPONSE_BITS_c);
    end if;
    return code;
  end function rest_key;

  type ct_ram_t is array (0 to 2 * 2 ** CBITS_c - 1) of std_logic_vector(CT_BITS_c - 1 downto 0);
  type head_ram_t is array (0 to BUCKETS_c - 1) of slot_t;
  -- a next pointer and whether it is NIL_c (the flag saves a compare after the block RAM's read)
  type next_ram_t is array (0 to 2 ** NBITS_c - 1) of std_logic_vector(SEL_SLOT_BITS_c downto 0);

  signal ct : ct_ram_t := (others => (others => '0'));
  -- the touched bits of the even and the odd cell row (two signals, not a two-entry array: GHDL
  -- 2.0 synthesises variable-indexed writes into small arrays wrongly, docs/netlist-sim.md)
  signal touched0 : std_logic_vector(CELLS_c - 1 downto 0) := (others => '0');
  signal touched1 : std_logic_vector(CELLS_c - 1 downto 0) := (others => '0');
  signal heads    : head_ram_t := (others => (others => '0'));
  signal nexts    : next_ram_t := (others => (others => '0'));
  -- the non-empty buckets but the lowest (whose top is c0, in registers)
  signal upper : std_logic_vector(BUCKETS_c - 1 downto 0) := (others => '0');

  -- frame state
  signal used : slot_t := (others => '0');
  -- the cell row each parity holds, and whether it holds one
  signal row_of0 : unsigned(CBITS_c - 1 downto 0) := (others => '0');
  signal row_of1 : unsigned(CBITS_c - 1 downto 0) := (others => '0');
  signal row_ok0 : std_logic := '0';
  signal row_ok1 : std_logic := '0';
  -- the rest holds a slot
  signal rest_any : std_logic := '0';
  -- the lowest non-empty bucket
  signal mb : code_t := (others => '0');
  -- its top slot (the next victim)
  signal c0 : slot_t := (others => '0');
  -- the slot below it (NIL_c: none), and c1 = NIL_c
  signal c1     : slot_t := (others => '0');
  signal c1_nil : std_logic := '0';
  -- c1 comes from the next-pointer RAM this clock
  signal c1_load : std_logic := '0';
  -- the next-pointer RAM's read register
  signal n_rd : std_logic_vector(SEL_SLOT_BITS_c downto 0) := (others => '0');
  -- the next-pointer RAM's write, registered: a decision's write lands a clock after it (before
  -- the next decision's read, at least two clocks after it), so that the decision's logic ends at
  -- flip-flops, not at the block RAM's data and enable inputs (their setup: docs/selection.md "Timing")
  signal nw_we : std_logic := '0';
  signal nw_a  : slot_t := (others => '0');
  signal nw_d  : std_logic_vector(SEL_SLOT_BITS_c downto 0) := (others => '0');

  -- stage m0: the candidate; m1, m2: the cell products
  signal v_m0, v_m1, v_m2          : std_logic := '0';
  signal low_m0, low_m1, low_m2    : std_logic := '0';
  signal code_m0, code_m1, code_m2 : code_t := (others => '0');
  signal key_m1, key_m2            : code_t := (others => '0');
  signal x_m0,   y_m0              : unsigned(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal kx_m0,  ky_m0             : map_t := (others => '0');
  signal ox_m0,  oy_m0             : map_t := (others => '0');
  signal ox_m1,  oy_m1             : map_t := (others => '0');
  signal px_m1                     : unsigned(COORD_BITS_c + CELL_SHIFT_c - 1 downto 0) := (others => '0');
  signal py_m1                     : unsigned(COORD_BITS_c + CELL_SHIFT_c - 1 downto 0) := (others => '0');
  signal px_m2                     : unsigned(MAP_BITS_c - 1 downto 0) := (others => '0');
  signal py_m2                     : unsigned(MAP_BITS_c - 1 downto 0) := (others => '0');

  -- stage d1: what the decision reads
  signal v_d1    : std_logic := '0';
  signal low_d1  : std_logic := '0';
  signal code_d1 : code_t := (others => '0');
  signal key_d1  : code_t := (others => '0');
  signal cx_d1   : cell_t := (others => '0');
  signal cy_d1   : cell_t := (others => '0');
  -- in the current row
  signal same_d1 : std_logic := '0';
  -- the cell has a floor (or is rejected)
  signal floor_d1 : std_logic := '0';
  signal rej_d1   : std_logic := '0';
  signal fkey_d1  : code_t := (others => '0');
  signal fslot_d1 : slot_t := (others => '0');
  -- the candidate's rank above the floor's; the floor's rest key and the candidate's against mb
  signal gt_d1  : std_logic := '0';
  signal fgt_d1 : std_logic := '0';
  signal feq_d1 : std_logic := '0';
  signal xgt_d1 : std_logic := '0';
  signal xeq_d1 : std_logic := '0';
  -- the top of the candidate's bucket
  signal hx_d1 : slot_t := (others => '0');
  -- the top of the floor's bucket
  signal hf_d1 : slot_t := (others => '0');
  -- the candidate's bucket is not empty
  signal bx_d1 : std_logic := '0';
  signal bf_d1 : std_logic := '0';
  -- the lowest bucket of upper: the lowest non-empty one above mb
  signal mb2_d1    : code_t := (others => '0');
  signal mb2_ok_d1 : std_logic := '0';
  -- used >= budget
  signal full_d1 : std_logic := '0';
  -- budget /= 0 (a frame parameter: steady from the frame's first candidate)
  signal budget_ok : std_logic := '0';

  -- stage d2: the decision
  signal v_out    : std_logic := '0';
  signal keep_out : std_logic := '0';
  signal slot_out : slot_t := (others => '0');
  signal new_out  : std_logic := '0';

  -- the index of v's lowest set bit (0 when none), in two levels: the lowest bit of each group of
  -- eight, and the lowest group holding one (v'length a multiple of 8, v'low = 0)
  function lowest_set (v : std_logic_vector) return natural is
    constant G_c : positive := v'length / 8;
    variable idx : natural;
    variable grp : natural;
    variable lo  : natural;
  begin
    grp := 0;
    for g in G_c - 1 downto 0 loop
      if v(8 * g + 7 downto 8 * g) /= x"00" then
        grp := g;
      end if;
    end loop;
    lo := 0;
    for i in 7 downto 0 loop
      if v(8 * grp + i) = '1' then
        lo := i;
      end if;
    end loop;
    idx := 8 * grp + lo;
    return idx;
  end function lowest_set;

begin

  -- the pipeline's registers from in_valid to out_valid: v_m0, v_m1, v_m2, v_d1, v_out
  assert FEAT_SELECT_LAT_c = 5
    report "orb_feat_select: FEAT_SELECT_LAT_c (orb_latency_pkg) must be this pipeline's 5 registers"
    severity failure;

  assert COLS_MAX_c < 2 ** GRID_BITS_c and ROWS_MAX_c < 2 ** GRID_BITS_c
    report "orb_feat_select: cols and rows (orb_limits_pkg) must fit GRID_BITS_c (orb_util_pkg)"
    severity failure;

  assert BUCKETS_c mod 8 = 0
    report "orb_feat_select: lowest_set takes groups of eight buckets (2 ** RESPONSE_BITS_c)"
    severity failure;

  assert SLOTS_g <= 4095
    report "orb_feat_select: SLOTS_g must be at most 4095 (slots 0 .. 4094; 4095 means none)"
    severity failure;

  pipe : process (clk) is
    variable ct_word : std_logic_vector(CT_BITS_c - 1 downto 0);
    variable cx, cy  : cell_t;
    -- decision
    variable rank_x   : rank_t;
    variable rank_r   : rank_t;  -- the floor's rank, read
    variable fkey_r   : code_t;
    variable from_fl  : boolean; -- the pushed one is the old floor (else the candidate)
    variable emptied  : boolean; -- the pop empties the lowest bucket
    variable p_lt     : boolean; -- the pushed key below the lowest bucket after the pop
    variable p_eq     : boolean; -- ... equal to it
    variable clr2     : boolean; -- the next bucket up becomes the lowest: its upper bit clears
    variable keep     : std_logic;
    variable new_slot : std_logic;
    variable slot     : slot_t;
    variable set_fl   : boolean; -- write the cell's floor (rank_x, slot)
    variable set_rej  : boolean;
    variable do_pop   : boolean;
    variable do_push  : boolean;
    -- pushed key and slot
    variable pq : code_t;
    variable ps : slot_t;
    -- the pushed bucket's top before the push
    variable ph      : slot_t;
    variable pb      : std_logic;
    variable up      : std_logic_vector(BUCKETS_c - 1 downto 0);
    variable n_mb    : code_t;
    variable n_c0    : slot_t;
    variable n_c1    : slot_t;
    variable n_c1nil : std_logic;
    variable n_load  : std_logic;
    variable n_any   : std_logic;
    variable n_addr  : slot_t;
    variable row_new : std_logic_vector(CELLS_c - 1 downto 0);
    variable same    : boolean;
    variable t_bits  : std_logic_vector(CELLS_c - 1 downto 0);
    -- one write port per RAM: (enable, address, data)
    variable n_we : boolean;
    variable n_wa : slot_t;
    variable n_wd : slot_t;
    variable n_wn : std_logic;   -- n_wd = NIL_c
    variable h_we : boolean;
    variable h_wa : code_t;
    variable h_wd : slot_t;
  begin
    if rising_edge(clk) then
      -- stage m0: the candidate
      v_m0 <= in_valid;
      if in_valid = '1' then
        x_m0    <= unsigned(in_x);
        y_m0    <= unsigned(in_y);
        low_m0  <= in_low;
        code_m0 <= unsigned(in_code);
        kx_m0   <= KX_ROM_c(to_integer(unsigned(cols)));
        ox_m0   <= OX_ROM_c(to_integer(unsigned(cols)));
        ky_m0   <= KY_ROM_c(to_integer(unsigned(rows)));
        oy_m0   <= OY_ROM_c(to_integer(unsigned(rows)));
      end if;
      -- stages m1, m2: x Kx + Ox and y Ky + Oy (DSP48 M and P registers)
      v_m1    <= v_m0;
      low_m1  <= low_m0;
      code_m1 <= code_m0;
      key_m1  <= rest_key(low_m0, code_m0);
      px_m1   <= x_m0 * kx_m0;
      py_m1   <= y_m0 * ky_m0;
      ox_m1   <= ox_m0;
      oy_m1   <= oy_m0;
      v_m2    <= v_m1;
      low_m2  <= low_m1;
      code_m2 <= code_m1;
      key_m2  <= key_m1;
      px_m2   <= resize(px_m1, MAP_BITS_c) + ox_m1;
      py_m2   <= resize(py_m1, MAP_BITS_c) + oy_m1;

      c1_load <= '0';

      -- stage d1: reads, and the decision's predicates (the state they read is the one the
      -- candidate's D2 sees: only a D2 changes it, and the one before was at least a clock earlier)
      v_d1    <= v_m2;
      low_d1  <= low_m2;
      code_d1 <= code_m2;
      key_d1  <= key_m2;
      cx      := resize(shift_right(px_m2, CELL_SHIFT_c), CBITS_c);
      cy      := resize(shift_right(py_m2, CELL_SHIFT_c), CBITS_c);
      cx_d1   <= cx;
      cy_d1   <= cy;
      if cy(0) = '0' then
        same   := row_ok0 = '1' and cy = row_of0;
        t_bits := touched0;
      else
        same   := row_ok1 = '1' and cy = row_of1;
        t_bits := touched1;
      end if;
      same_d1  <= bool2sl(same);
      ct_word  := ct(to_integer(cy(0 downto 0) & cx));
      rank_r   := unsigned(ct_word(SEL_SLOT_BITS_c + RESPONSE_BITS_c downto SEL_SLOT_BITS_c));
      fkey_r   := unsigned(ct_word(CT_BITS_c - 2 downto SEL_SLOT_BITS_c + RESPONSE_BITS_c + 1));
      floor_d1 <= bool2sl(same) and t_bits(to_integer(cx));
      rej_d1   <= ct_word(CT_BITS_c - 1);
      fkey_d1  <= fkey_r;
      fslot_d1 <= unsigned(ct_word(SEL_SLOT_BITS_c - 1 downto 0));
      gt_d1    <= bool2sl(((not low_m2) & code_m2) > rank_r);
      fgt_d1   <= bool2sl(fkey_r > mb);
      feq_d1   <= bool2sl(fkey_r = mb);
      xgt_d1   <= bool2sl(key_m2 > mb);
      xeq_d1   <= bool2sl(key_m2 = mb);
      hx_d1    <= heads(to_integer(key_m2));
      bx_d1    <= upper(to_integer(key_m2));
      hf_d1    <= heads(to_integer(fkey_r));
      bf_d1    <= upper(to_integer(fkey_r));
      mb2_d1    <= to_unsigned(lowest_set(upper), RESPONSE_BITS_c);
      mb2_ok_d1 <= bool2sl(upper /= (upper'range => '0'));
      full_d1   <= bool2sl(used >= unsigned(budget));
      budget_ok <= bool2sl(unsigned(budget) /= 0);

      -- stage d2: the decision and its writes
      v_out    <= v_d1;
      keep     := '0';
      new_slot := '0';
      slot     := (others => '0');
      set_fl   := false;
      set_rej  := false;
      do_pop   := false;
      do_push  := false;
      from_fl  := false;
      rank_x   := (not low_d1) & code_d1;
      if v_d1 = '1' and grid = '0' then
        keep     := not low_d1;
        new_slot := '1';
      elsif v_d1 = '1' and budget_ok = '1' then
        if floor_d1 = '0' then
          -- (a) the cell's first candidate: its floor
          if full_d1 = '0' then
            keep := '1';
            new_slot := '1';
            slot := used;
            set_fl := true;
          elsif rest_any = '1' then
            keep := '1';
            slot := c0;
            do_pop := true;
            set_fl := true;
          else
            -- the level holds nothing but floors
            set_rej := true;
          end if;
        elsif rej_d1 = '1' then
          -- a cell that found no place stays without one
          null;
        elsif gt_d1 = '1' then
          -- (b) a record: the new floor
          keep := '1';
          set_fl := true;
          from_fl := true;
          -- the old floor joins the rest (a low one at key 0)
          if full_d1 = '0' then
            new_slot := '1';
            slot := used;
            do_push := true;
          -- the rest's lowest goes, the old floor stays
          elsif rest_any = '1' and fgt_d1 = '1' then
            slot := c0;
            do_pop := true;
            do_push := true;
          -- the old floor is the lowest: it goes
          else
            slot := fslot_d1;
          end if;
        else
          -- (c) a candidate for the rest (a low one, key 0, only takes a free place)
          if full_d1 = '0' then
            keep := '1';
            new_slot := '1';
            slot := used;
            do_push := true;
          elsif rest_any = '1' and xgt_d1 = '1' then
            keep := '1';
            slot := c0;
            do_pop := true;
            do_push := true;
          end if;
        end if;
      end if;
      keep_out <= keep;
      new_out  <= new_slot;
      slot_out <= slot;
      if new_slot = '1' and grid = '1' then
        used <= used + 1;
      end if;

      -- the cell table row: a new row starts with no cell touched
      if v_d1 = '1' and grid = '1' and (set_fl or set_rej) then
        if cy_d1(0) = '0' then
          row_new := touched0;
        else
          row_new := touched1;
        end if;
        if same_d1 = '0' then
          row_new := (others => '0');
        end if;
        row_new(to_integer(cx_d1)) := '1';
        if cy_d1(0) = '0' then
          touched0 <= row_new;
          if same_d1 = '0' then
            row_of0 <= cy_d1;
            row_ok0 <= '1';
          end if;
        else
          touched1 <= row_new;
          if same_d1 = '0' then
            row_of1 <= cy_d1;
            row_ok1 <= '1';
          end if;
        end if;
        ct(to_integer(cy_d1(0 downto 0) & cx_d1)) <= bool2sl(set_rej) & std_logic_vector(key_d1) &
                                                     std_logic_vector(rank_x) & std_logic_vector(slot);
      end if;

      -- the pushed key and slot, the top of its bucket before the push, and how the key compares
      -- with the lowest bucket after the pop: mb, or the next one up when the pop empties mb (both
      -- sources compared in parallel and selected after, not one compare of a selected code: the
      -- decision clock's depth, docs/selection.md "Timing")
      emptied := do_pop and c1_nil = '1';
      if from_fl then
        pq  := fkey_d1;
        ps  := fslot_d1;
        ph  := hf_d1;
        pb  := bf_d1;
        if emptied then
          p_lt := fkey_d1 < mb2_d1;
          p_eq := fkey_d1 = mb2_d1;
        else
          p_lt := fgt_d1 = '0' and feq_d1 = '0';
          p_eq := feq_d1 = '1';
        end if;
      else
        pq  := key_d1;
        ps  := slot;
        ph  := hx_d1;
        pb  := bx_d1;
        if emptied then
          p_lt := key_d1 < mb2_d1;
          p_eq := key_d1 = mb2_d1;
        else
          p_lt := xgt_d1 = '0' and xeq_d1 = '0';
          p_eq := xeq_d1 = '1';
        end if;
      end if;

      -- the rest: pop the lowest bucket's top, push (pq, ps); the lowest bucket stays in registers,
      -- `upper` marks the other non-empty buckets (their tops are in the heads RAM)
      up     := upper;
      clr2   := false;
      n_mb   := mb;
      n_c0   := c0;
      n_c1   := c1;
      n_c1nil := c1_nil;
      n_load := '0';
      n_any  := rest_any;
      -- the prefetch's address: the slot below the lowest bucket's top, or the next bucket's top
      -- when there is none. It is used only after a pop, which empties the bucket exactly when
      -- c1_nil is set, so it needs none of the decision's logic (the read address's timing)
      if c1_nil = '1' then
        n_addr := heads(to_integer(mb2_d1));
      else
        n_addr := c1;
      end if;
      n_we   := false;
      n_wa   := ps;
      n_wd   := NIL_c;
      n_wn   := '1';
      h_we   := false;
      h_wa   := pq;
      h_wd   := ps;
      if do_pop then
        -- the bucket goes on: its next slot, and the one below it fetched
        if not emptied then
          n_c0   := c1;
          n_load := '1';
        -- the bucket empties: the next bucket up becomes the lowest
        elsif mb2_ok_d1 = '1' then
          clr2   := true;
          n_mb   := mb2_d1;
          n_c0   := heads(to_integer(mb2_d1));
          n_load := '1';
        else
          n_any := '0';
        end if;
      end if;
      if do_push then
        -- the pushed slot's next pointer: NIL_c unless set below
        n_we := true;
        -- the rest was empty: the pushed slot alone is the lowest bucket
        if n_any = '0' then
          n_mb := pq;
          n_c0 := ps;
          n_c1 := NIL_c;
          n_c1nil := '1';
          n_load := '0';
          n_any := '1';
        -- below the lowest: it becomes the lowest, the old one goes to the heads RAM (after a pop
        -- the old one is the next bucket up, whose top is still there)
        elsif p_lt then
          if do_pop then
            clr2 := false;
          else
            h_we := true;
            h_wa := mb;
            h_wd := c0;
            up(to_integer(mb)) := '1';
          end if;
          n_mb := pq;
          n_c0 := ps;
          n_c1 := NIL_c;
          n_c1nil := '1';
          n_load := '0';
        -- onto the lowest bucket (LIFO): on top of its cached top
        elsif p_eq then
          n_wd := n_c0;
          n_wn := '0';
          n_c1 := n_c0;
          n_c1nil := '0';
          n_c0 := ps;
          n_load := '0';
        -- onto a bucket above: through the heads table
        else
          if pb = '1' then
            n_wd := ph;
            n_wn := '0';
          end if;
          h_we := true;
          h_wa := pq;
          h_wd := ps;
          up(to_integer(pq)) := '1';
        end if;
      end if;
      -- (one write at mb2_d1's bit: GHDL 2.0's synthesis fails on two)
      if clr2 then
        up(to_integer(mb2_d1)) := '0';
      end if;
      nw_we <= bool2sl(v_d1 = '1' and grid = '1' and n_we);
      nw_a  <= n_wa;
      nw_d  <= n_wn & std_logic_vector(n_wd);
      if nw_we = '1' then
        nexts(to_integer(nw_a(NBITS_c - 1 downto 0))) <= nw_d;
      end if;
      if v_d1 = '1' and grid = '1' then
        if h_we then
          heads(to_integer(h_wa)) <= h_wd;
        end if;
      end if;
      if v_d1 = '1' and grid = '1' then
        upper    <= up;
        mb       <= n_mb;
        c0       <= n_c0;
        rest_any <= n_any;
        if n_load = '1' then
          c1_load <= '1';
        else
          c1     <= n_c1;
          c1_nil <= n_c1nil;
        end if;
      end if;
      n_rd <= nexts(to_integer(n_addr(NBITS_c - 1 downto 0)));
      -- the prefetched slot below the lowest bucket's top (read issued at the last D2; no decision
      -- is made in the clock after one)
      if c1_load = '1' then
        c1     <= unsigned(n_rd(SEL_SLOT_BITS_c - 1 downto 0));
        c1_nil <= n_rd(SEL_SLOT_BITS_c);
      end if;

      -- pragma translate_off
      assert not (in_valid = '1' and v_m0 = '1')
        report "orb_feat_select: candidates in consecutive clocks (at most one every second clock)"
        severity failure;
      -- pragma translate_on
      if in_done = '1' or rst = '1' then
        used     <= (others => '0');
        row_ok0  <= '0';
        row_ok1  <= '0';
        rest_any <= '0';
        upper    <= (others => '0');
        touched0 <= (others => '0');
        touched1 <= (others => '0');
      end if;
      if rst = '1' then
        nw_we <= '0';
        v_m0  <= '0';
        v_m1  <= '0';
        v_m2  <= '0';
        v_d1  <= '0';
        v_out <= '0';
      end if;
    end if;
  end process pipe;

  out_valid <= v_out;
  out_keep  <= keep_out;
  out_slot  <= std_logic_vector(slot_out);
  out_new   <= new_out;

end architecture rtl;
