-- SPDX-License-Identifier: MIT
-- orb_axil_regs: the accelerator's AXI4-Lite register bank (map in orb_regs_pkg, generated from
-- golden_model/data/regmap.json; table and bus rules in docs/registers.md, design in
-- docs/axil-regs.md). It reads back the configuration generics, drives the control outputs
-- (enable, a one-clock soft_reset pulse, mode_orb, the FAST thresholds and the selection
-- (select_grid, grid_cols, grid_rows, budget), which the core applies from the next frame on), shows the status inputs of the other blocks, keeps the
-- interrupt enable and W1C status bits (set by frame_done_pulse and error_pulse; irq is the
-- registered OR(status AND enable): latency AXIL_IRQ_LAT_c = 2 clocks from the pulse,
-- orb_latency_pkg, docs/latency.md) and pulses release_valid with release_bank when the CPU
-- writes BANK_RELEASE. For the DDR feature memory orb_feat_dma (docs/feature-dma.md) it holds the
-- ring (ring_base, ring_stride, ring_count from RING_BASE, RING_STRIDE, RING_COUNT), pulses
-- ring_release_valid with ring_release_index when the CPU writes RING_RELEASE, shows the ring's
-- status and counters (RING_STATUS, RING_INFO, DMA_*; inputs that read 0 when left unconnected)
-- and reads back MEM_DDR_g and the DDR window in CFG_DDR. One transaction per channel at a
-- time: AW and W are each held in a one-entry buffer (awready/wready low while it is full) and
-- may come in any order and with any delay; the write is decoded once both are there and no B
-- response is pending (or it is taken at that edge), and executed with its B response one clock
-- later; arready is low from an AR handshake until its R handshake. A register read answers on
-- R one clock after the AR handshake. Memory port contract: every 32-bit aligned read at MEM_BASE_c or above
-- raises mem_rd_en for one clock with mem_rd_addr = address - MEM_BASE_c (a byte offset, bits
-- 1..0 zero); orb_feat_mem must drive the word on mem_rd_data so that it is valid at the
-- MEM_LATENCY_g-th rising edge after the edge that sampled mem_rd_en = '1' (1: block RAM
-- output, 2: block RAM with output register), where it is taken and returned with OKAY.
-- SLVERR (no state change) answers misaligned or unknown addresses, writes to ro registers and to
-- the memory window, reads of the wo BANK_RELEASE and RING_RELEASE, and rw/wo writes that set a
-- reserved bit or give a field a value outside its minimum and maximum (CTRL.mode 2 or 3,
-- BANK_RELEASE.bank >= BANKS_c, SELECT.cols or SELECT.rows 0, SELECT.budget above MEM_DEPTH_g - 1,
-- RING_COUNT.count above 16); byte strobes are honoured (merged into the current value before
-- that check). rst resets the control state and every register to its documented reset value.
-- The decode is data: a register file driven by orb_regs_pkg's tables REGS_c (offset, access,
-- defined bits, reset value, live and pulse bits per register) and REG_LIMITS_c (field minima and
-- maxima; a maximum marked `depth` is MEM_DEPTH_g - 1),
-- generated from the map. Per-register code is only wiring: the `wiring` process (ro fields that
-- follow a generic or an input port, w1c set inputs) and the output assignments at the end.
-- Ports and generics: docs/entities/orb_axil_regs.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_regs_pkg.all;
use work.orb_regs_types_pkg.all;
use work.orb_limits_pkg.all;

-- the DDR ring's inputs have defaults: orb_accel_top may leave them unconnected (a BRAM build)
-- vsg_off port_012
entity orb_axil_regs is
  generic (
    WIDTH_g       : width_t                      := 640;
    HEIGHT_g      : height_t                     := 480;
    SCALES_g      : scales_t                     := 1;
    STEP_NUM_g    : step_num_t                   := 2;    -- pyramid step, read back in CFG_ORB
    STEP_DEN_g    : step_den_t                   := 1;
    SECTORS_g     : sectors_t                    := 32;   -- orientation sectors in all (orb_limits_pkg)
    MEM_DEPTH_g   : positive range 1 to 16777215 := 4096; -- read back only (CFG_MEM.depth)
    MEM_LATENCY_g : positive range 1 to 8        := 2;    -- mem_rd_en to mem_rd_data, clocks
    ADDR_BITS_g   : positive range 18 to 20      := 18;
    -- the DDR feature memory (docs/feature-dma.md), read back in CFG_DDR: 1 if the features go to the
    -- DDR ring, and the DDR window the ring must lie in (MiB)
    MEM_DDR_g     : natural range 0 to 1    := 0;
    WIN_BASE_MB_g : natural range 0 to 4095 := 0;
    WIN_SIZE_MB_g : natural range 1 to 4096 := 4096
  );
  port (
    clk : in    std_logic;
    rst : in    std_logic;
    -- AXI4-Lite slave
    s_axil_awaddr  : in    std_logic_vector(ADDR_BITS_g - 1 downto 0);
    s_axil_awprot  : in    std_logic_vector(2 downto 0);
    s_axil_awvalid : in    std_logic;
    s_axil_awready : out   std_logic;
    s_axil_wdata   : in    std_logic_vector(31 downto 0);
    s_axil_wstrb   : in    std_logic_vector(3 downto 0);
    s_axil_wvalid  : in    std_logic;
    s_axil_wready  : out   std_logic;
    s_axil_bresp   : out   std_logic_vector(1 downto 0);
    s_axil_bvalid  : out   std_logic;
    s_axil_bready  : in    std_logic;
    s_axil_araddr  : in    std_logic_vector(ADDR_BITS_g - 1 downto 0);
    s_axil_arprot  : in    std_logic_vector(2 downto 0);
    s_axil_arvalid : in    std_logic;
    s_axil_arready : out   std_logic;
    s_axil_rdata   : out   std_logic_vector(31 downto 0);
    s_axil_rresp   : out   std_logic_vector(1 downto 0);
    s_axil_rvalid  : out   std_logic;
    s_axil_rready  : in    std_logic;
    -- control
    enable     : out   std_logic;
    soft_reset : out   std_logic;
    mode_orb   : out   std_logic;
    threshold  : out   std_logic_vector(7 downto 0);
    -- low threshold and selection (docs/selection.md); budget is at most MEM_DEPTH_g - 1
    threshold_lo : out   std_logic_vector(7 downto 0);
    select_grid  : out   std_logic;
    grid_cols    : out   std_logic_vector(SELECT_COLS_MSB_c - SELECT_COLS_LSB_c downto 0);
    grid_rows    : out   std_logic_vector(SELECT_ROWS_MSB_c - SELECT_ROWS_LSB_c downto 0);
    budget       : out   std_logic_vector(SELECT_BUDGET_MSB_c - SELECT_BUDGET_LSB_c downto 0);
    -- status from the other blocks
    frame_count    : in    std_logic_vector(31 downto 0);
    dropped        : in    std_logic_vector(31 downto 0);
    proto_errors   : in    std_logic_vector(31 downto 0);
    bank_ready     : in    std_logic_vector(BANKS_c - 1 downto 0);
    last_bank      : in    std_logic;
    overflow       : in    std_logic;
    bank0_count    : in    std_logic_vector(15 downto 0);
    bank0_frame    : in    std_logic_vector(15 downto 0);
    bank1_count    : in    std_logic_vector(15 downto 0);
    bank1_frame    : in    std_logic_vector(15 downto 0);
    overrun        : in    std_logic_vector(31 downto 0);
    overflow_count : in    std_logic_vector(31 downto 0);
    desc_lost      : in    std_logic_vector(31 downto 0);
    discarded      : in    std_logic_vector(31 downto 0);
    -- interrupts
    frame_done_pulse : in    std_logic;
    error_pulse      : in    std_logic;
    irq              : out   std_logic;
    -- feature memory: bank release and read port
    release_valid : out   std_logic;
    release_bank  : out   std_logic_vector(BANK_RELEASE_BANK_MSB_c - BANK_RELEASE_BANK_LSB_c downto 0);
    mem_rd_en     : out   std_logic;
    mem_rd_addr   : out   std_logic_vector(ADDR_BITS_g - 1 downto 0);
    mem_rd_data   : in    std_logic_vector(31 downto 0);
    -- DDR ring (orb_feat_dma, docs/feature-dma.md): configuration and release
    ring_base          : out   std_logic_vector(31 downto 0);
    ring_stride        : out   std_logic_vector(31 downto 0);
    ring_count         : out   std_logic_vector(RING_COUNT_COUNT_MSB_c - RING_COUNT_COUNT_LSB_c downto 0);
    ring_release_valid : out   std_logic;
    ring_release_index : out   std_logic_vector(RING_RELEASE_INDEX_MSB_c - RING_RELEASE_INDEX_LSB_c downto 0);
    -- DDR ring status and counters (0 when unconnected: a build without orb_feat_dma)
    ring_ready      : in    std_logic_vector(15 downto 0) := (others => '0');
    ring_last       : in    std_logic_vector(3 downto 0)  := (others => '0');
    ring_error      : in    std_logic_vector(3 downto 0)  := (others => '0');
    ring_busy       : in    std_logic                     := '0';
    ring_last_count : in    std_logic_vector(15 downto 0) := (others => '0');
    ring_last_frame : in    std_logic_vector(15 downto 0) := (others => '0');
    dma_dropped     : in    std_logic_vector(31 downto 0) := (others => '0');
    dma_bus_errors  : in    std_logic_vector(31 downto 0) := (others => '0');
    dma_beats       : in    std_logic_vector(31 downto 0) := (others => '0')
  );
end entity orb_axil_regs;
-- vsg_on port_012

architecture rtl of orb_axil_regs is

  subtype word_t is std_logic_vector(s_axil_wdata'range);
  subtype strobes_t is std_logic_vector(s_axil_wstrb'range);
  subtype resp_t is std_logic_vector(s_axil_bresp'range);

  type word_array_t is array (natural range <>) of word_t;

  subtype reg_words_t is word_array_t(REGS_c'range);

  constant OKAY_c   : resp_t := "00";
  constant SLVERR_c : resp_t := "10";
  constant ZERO_c   : word_t := (others => '0');

  -- the largest legal value of a limited field, in place: its max, or MEM_DEPTH_g - 1 (at most the
  -- field's all-ones value) for a `depth` limit
  function limit_max (lim : reg_limit_t) return unsigned is
    constant DEPTH_BITS_c : positive := 24;  -- MEM_DEPTH_g < 2 ** 24
    variable top_v        : unsigned(word_t'length + DEPTH_BITS_c - 1 downto 0);
  begin
    if lim.depth then
      top_v := shift_left(resize(to_unsigned(MEM_DEPTH_g - 1, DEPTH_BITS_c), top_v'length), lim.lsb);
      if top_v < resize(unsigned(lim.max), top_v'length) then
        return top_v(word_t'range);
      end if;
    end if;
    return unsigned(lim.max);
  end function limit_max;

  -- word with bits msb .. lsb set to value
  function put (word : word_t; value : natural; msb, lsb : natural) return word_t is
    variable word_v : word_t := word;
  begin
    word_v(msb downto lsb) := std_logic_vector(to_unsigned(value, msb - lsb + 1));
    return word_v;
  end function put;

  function put (word : word_t; value : std_logic_vector; msb, lsb : natural) return word_t is
    variable word_v : word_t := word;
  begin
    word_v(msb downto lsb) := value;
    return word_v;
  end function put;

  -- w when cond, else zero
  function sel (cond : boolean; w : word_t) return word_t is
  begin
    if cond then
      return w;
    end if;
    return ZERO_c;
  end function sel;

  -- the 32-bit mask of the bytes whose strobe is set
  function byte_mask (strb : strobes_t) return word_t is
    variable mask_v : word_t;
  begin
    for i in strb'range loop
      mask_v(8 * i + 7 downto 8 * i) := (others => strb(i));
    end loop;
    return mask_v;
  end function byte_mask;

  -- log2(MEM_BASE_c), a power of two: address bits LOW_BITS_c - 1 .. 2 select a register
  function low_bits return positive is
  begin
    for n in 2 to 30 loop
      if 2 ** n >= MEM_BASE_c then
        return n;
      end if;
    end loop;
    return 30;
  end function low_bits;

  constant LOW_BITS_c : positive := low_bits;

  -- the bits of a register held in flip-flops: the fields of rw, w1c and wo registers except pulses
  function stored (d : reg_desc_t) return word_t is
  begin
    if d.acc = access_ro then
      return ZERO_c;
    end if;
    return d.mask and not d.pulse;
  end function stored;

  -- the word a read returns (reserved bits and pulse fields 0; wo registers are not readable)
  function read_value (d : reg_desc_t; held, live : word_t) return word_t is
  begin
    if d.acc = access_ro then
      return (d.reset and not d.live) or (live and d.live);
    elsif d.acc = access_wo then
      return ZERO_c;
    end if;
    return held and stored(d);
  end function read_value;

  -- write channel (process write_capture): the AW and W buffers, the one write in flight
  -- (decoded_valid: decoded, executed at the next edge) and the B response
  signal aw_full       : std_logic := '0';
  signal aw_addr       : std_logic_vector(ADDR_BITS_g - 1 downto 0) := (others => '0');
  signal w_full        : std_logic := '0';
  signal w_data        : word_t := (others => '0');
  signal w_strb        : strobes_t := (others => '0');
  signal decoded_valid : std_logic := '0';
  signal bvalid_r      : std_logic := '0';
  signal bresp_r       : resp_t := OKAY_c;
  -- the buffered write is decoded at this edge: AW and W there, no B response pending (or it is
  -- taken at this edge), no decoded write waiting
  signal write_take : boolean;

  -- a decoded write (process write_decode), executed by the register file at the next edge
  type decoded_t is record
    ok     : std_logic;                          -- legal: executed, OKAY; else no change, SLVERR
    hit    : std_logic_vector(REGS_c'range);     -- the register written (at most one)
    merged : word_t;                             -- its new value: the strobed bytes merged in
    bytes  : word_t;                             -- the strobed bytes' mask
  end record decoded_t;

  signal decoded : decoded_t := (ok => '0', hit => (others => '0'), merged => (others => '0'),
                                 bytes => (others => '0'));

  -- read channel and memory port (process rd)
  signal ar_busy  : std_logic := '0';
  signal rvalid_r : std_logic := '0';
  signal rresp_r  : resp_t := OKAY_c;
  signal rdata_r  : word_t := (others => '0');
  signal mem_en_r : std_logic := '0';
  signal mem_addr : std_logic_vector(ADDR_BITS_g - 1 downto 0) := (others => '0');
  signal mem_pipe : std_logic_vector(MEM_LATENCY_g - 1 downto 0) := (others => '0');

  -- the register file (process reg_file), indexed as REGS_c: stored bits (only stored(REGS_c(i))
  -- ever leave 0; power-up value 0, rst loads the reset values), pulse fields for one clock after a
  -- write, wo registers' one-clock write strobe
  signal held     : reg_words_t := (others => ZERO_c);
  signal pulses   : reg_words_t := (others => ZERO_c);
  signal written  : std_logic_vector(REGS_c'range) := (others => '0');
  signal budget_r : std_logic_vector(budget'range) := (others => '0');
  signal irq_r    : std_logic := '0';

  -- wired inputs: values of the live (generic or port) ro fields, set pulses of w1c bits
  signal live_in : reg_words_t;
  signal w1c_set : reg_words_t;

begin

  assert sectors_legal(SECTORS_g)
    report "orb_axil_regs: SECTORS_g (sectors in all) must be " & SECTORS_TEXT_c
    severity failure;
  assert 2 ** ADDR_BITS_g > MEM_BASE_c
    report "orb_axil_regs: ADDR_BITS_g leaves no feature-memory window above MEM_BASE_c"
    severity failure;
  assert STATUS_BANK_READY_MSB_c - STATUS_BANK_READY_LSB_c + 1 = BANKS_c and BANK_RELEASE_BANK_MAX_c = BANKS_c - 1
    report "orb_axil_regs: orb_regs_pkg's bank fields do not match BANKS_c"
    severity failure;
  assert RING_COUNT_COUNT_MAX_c = ring_ready'length and 2 ** ring_release_index'length = ring_ready'length
         and RING_STATUS_READY_MSB_c - RING_STATUS_READY_LSB_c + 1 = ring_ready'length
    report "orb_axil_regs: orb_regs_pkg's ring fields do not match the 16 ring buffers of ring_ready"
    severity failure;
  assert REG_IRQ_STATUS_MASK_c = REG_IRQ_ENABLE_MASK_c and REGS_c(REG_IRQ_STATUS_IDX_c).acc = access_w1c
         and IRQ_STATUS_FRAME_DONE_LSB_c = IRQ_ENABLE_FRAME_DONE_LSB_c
         and IRQ_STATUS_ERROR_LSB_c = IRQ_ENABLE_ERROR_LSB_c
    report "orb_axil_regs: IRQ_STATUS (w1c) and IRQ_ENABLE must have their fields at the same bits"
    severity failure;

  -- Wiring, the only per-register code: the ro fields that follow a generic or an input port
  -- (REGS_c(i).live) and the inputs that set w1c bits. Bits outside those fields are ignored.
  wiring : process (all) is
    variable live_v : reg_words_t;
    variable set_v  : reg_words_t;
  begin
    live_v                        := (others => ZERO_c);
    set_v                         := (others => ZERO_c);
    live_v(REG_CFG_SIZE_IDX_c)        := put(put(ZERO_c, WIDTH_g, CFG_SIZE_WIDTH_MSB_c, CFG_SIZE_WIDTH_LSB_c),
                                             HEIGHT_g, CFG_SIZE_HEIGHT_MSB_c, CFG_SIZE_HEIGHT_LSB_c);
    live_v(REG_CFG_ORB_IDX_c)         := put(put(put(put(ZERO_c, SCALES_g, CFG_ORB_SCALES_MSB_c, CFG_ORB_SCALES_LSB_c),
                                                     SECTORS_g, CFG_ORB_SECTORS_MSB_c, CFG_ORB_SECTORS_LSB_c),
                                                 STEP_NUM_g, CFG_ORB_STEP_NUM_MSB_c, CFG_ORB_STEP_NUM_LSB_c),
                                             STEP_DEN_g, CFG_ORB_STEP_DEN_MSB_c, CFG_ORB_STEP_DEN_LSB_c);
    live_v(REG_CFG_MEM_IDX_c)         := put(put(ZERO_c, MEM_DEPTH_g, CFG_MEM_DEPTH_MSB_c, CFG_MEM_DEPTH_LSB_c),
                                             MEM_LATENCY_g, CFG_MEM_LATENCY_MSB_c, CFG_MEM_LATENCY_LSB_c);
    live_v(REG_STATUS_IDX_c)          := put(put(put(ZERO_c, bank_ready, STATUS_BANK_READY_MSB_c, STATUS_BANK_READY_LSB_c),
                                             (0 => last_bank), STATUS_LAST_BANK_MSB_c, STATUS_LAST_BANK_LSB_c),
                                         (0 => overflow), STATUS_OVERFLOW_MSB_c, STATUS_OVERFLOW_LSB_c);
    live_v(REG_FRAME_COUNT_IDX_c)     := frame_count;
    live_v(REG_DROPPED_IDX_c)         := dropped;
    live_v(REG_PROTO_ERRORS_IDX_c)    := proto_errors;
    live_v(REG_BANK0_INFO_IDX_c)      := put(put(ZERO_c, bank0_count, BANK0_INFO_COUNT_MSB_c, BANK0_INFO_COUNT_LSB_c),
                                             bank0_frame, BANK0_INFO_FRAME_MSB_c, BANK0_INFO_FRAME_LSB_c);
    live_v(REG_BANK1_INFO_IDX_c)      := put(put(ZERO_c, bank1_count, BANK1_INFO_COUNT_MSB_c, BANK1_INFO_COUNT_LSB_c),
                                             bank1_frame, BANK1_INFO_FRAME_MSB_c, BANK1_INFO_FRAME_LSB_c);
    live_v(REG_OVERRUN_IDX_c)         := overrun;
    live_v(REG_OVERFLOW_COUNT_IDX_c)  := overflow_count;
    live_v(REG_DESC_LOST_IDX_c)       := desc_lost;
    live_v(REG_DISCARDED_IDX_c)       := discarded;
    live_v(REG_RING_STATUS_IDX_c)     := put(put(ZERO_c, ring_ready, RING_STATUS_READY_MSB_c, RING_STATUS_READY_LSB_c),
                                             ring_last, RING_STATUS_LAST_MSB_c, RING_STATUS_LAST_LSB_c);
    live_v(REG_RING_STATUS_IDX_c)     := put(put(live_v(REG_RING_STATUS_IDX_c),
                                                 ring_error, RING_STATUS_ERROR_MSB_c, RING_STATUS_ERROR_LSB_c),
                                             (0 => ring_busy), RING_STATUS_BUSY_MSB_c, RING_STATUS_BUSY_LSB_c);
    live_v(REG_RING_INFO_IDX_c)       := put(put(ZERO_c, ring_last_count, RING_INFO_COUNT_MSB_c, RING_INFO_COUNT_LSB_c),
                                             ring_last_frame, RING_INFO_FRAME_MSB_c, RING_INFO_FRAME_LSB_c);
    live_v(REG_DMA_DROPPED_IDX_c)     := dma_dropped;
    live_v(REG_DMA_BUS_ERRORS_IDX_c)  := dma_bus_errors;
    live_v(REG_DMA_BEATS_IDX_c)       := dma_beats;
    live_v(REG_CFG_DDR_IDX_c)         := put(put(put(ZERO_c, MEM_DDR_g, CFG_DDR_DDR_MSB_c, CFG_DDR_DDR_LSB_c),
                                                 WIN_BASE_MB_g, CFG_DDR_WIN_BASE_MSB_c, CFG_DDR_WIN_BASE_LSB_c),
                                             WIN_SIZE_MB_g, CFG_DDR_WIN_SIZE_MSB_c, CFG_DDR_WIN_SIZE_LSB_c);
    set_v(REG_IRQ_STATUS_IDX_c)      := put(put(ZERO_c, (0 => frame_done_pulse), IRQ_STATUS_FRAME_DONE_MSB_c,
                                             IRQ_STATUS_FRAME_DONE_LSB_c),
                                         (0 => error_pulse), IRQ_STATUS_ERROR_MSB_c, IRQ_STATUS_ERROR_LSB_c);
    live_in <= live_v;
    w1c_set <= set_v;
  end process wiring;

  -- Write capture: the AW and W buffers (either may come first, with any delay), the one write in
  -- flight and the B response. A write takes two clocks: decoded (process write_decode) at the
  -- edge after AW and W are both there, executed (process reg_file) with its B response at the
  -- next, so that neither half is a long path (docs/synthesis.md, "Timing"). No other write is
  -- decoded in between; the next one is decoded at the earliest at the edge that takes this one's
  -- B response, so writes still complete at one per 2 clocks.
  write_take <= aw_full = '1' and w_full = '1' and (bvalid_r = '0' or s_axil_bready = '1') and decoded_valid = '0';

  write_capture : process (clk) is
  begin
    if rising_edge(clk) then
      if s_axil_awvalid = '1' and aw_full = '0' then
        aw_addr <= s_axil_awaddr;
        aw_full <= '1';
      end if;
      if s_axil_wvalid = '1' and w_full = '0' then
        w_data <= s_axil_wdata;
        w_strb <= s_axil_wstrb;
        w_full <= '1';
      end if;
      if bvalid_r = '1' and s_axil_bready = '1' then
        bvalid_r <= '0';
      end if;
      if write_take then
        aw_full       <= '0';
        w_full        <= '0';
        decoded_valid <= '1';
      end if;
      if decoded_valid = '1' then
        decoded_valid <= '0';
        bvalid_r      <= '1';
        bresp_r       <= OKAY_c when decoded.ok = '1' else SLVERR_c;
      end if;
      if rst = '1' then
        aw_full       <= '0';
        w_full        <= '0';
        bvalid_r      <= '0';
        decoded_valid <= '0';
      end if;
    end if;
  end process write_capture;

  -- Write decode: an aligned address below MEM_BASE_c naming a writable register. Each register's
  -- merged value (its current value for rw, zero for w1c and wo, under the strobed bytes of the
  -- data) and legality (no reserved bit set, w1c registers ignore them; no field outside its
  -- limits) are formed in parallel from the data alone, and the address only picks one: the
  -- legality is not behind the address decode (docs/synthesis.md, "Timing").
  write_decode : process (clk) is
    variable index_v   : natural; -- the word address below MEM_BASE_c
    variable in_regs_v : boolean; -- aligned and below MEM_BASE_c
    variable bytes_v   : word_t;
    variable hit_v     : std_logic_vector(REGS_c'range);
    variable current_v : word_t;
    variable reg_new_v : word_t;  -- register i's value after the write
    variable legal_v   : boolean; -- ... and whether it is legal
    variable merged_v  : word_t;
    variable ok_v      : boolean;
  begin
    if rising_edge(clk) then
      if write_take then
        index_v   := to_integer(unsigned(aw_addr(LOW_BITS_c - 1 downto 2)));
        in_regs_v := aw_addr(1 downto 0) = "00" and unsigned(aw_addr(ADDR_BITS_g - 1 downto LOW_BITS_c)) = 0;
        bytes_v   := byte_mask(w_strb);
        hit_v     := (others => '0');
        ok_v      := false;
        merged_v  := ZERO_c;
        for i in REGS_c'range loop
          if in_regs_v and index_v = REGS_c(i).offset / 4 and REGS_c(i).acc /= access_ro then
            hit_v(i) := '1';
          end if;
          current_v := ZERO_c;
          if REGS_c(i).acc = access_rw then
            current_v := read_value(REGS_c(i), held(i), live_in(i));
          end if;
          reg_new_v := (current_v and not bytes_v) or (w_data and bytes_v);
          legal_v   := REGS_c(i).acc = access_w1c or (reg_new_v and not REGS_c(i).mask) = ZERO_c;
          for k in REG_LIMITS_c'range loop
            if REG_LIMITS_c(k).reg = i and
               (unsigned(reg_new_v and REG_LIMITS_c(k).mask) > limit_max(REG_LIMITS_c(k)) or
                unsigned(reg_new_v and REG_LIMITS_c(k).mask) < unsigned(REG_LIMITS_c(k).min)) then
              legal_v := false;
            end if;
          end loop;
          merged_v := merged_v or sel(hit_v(i) = '1', reg_new_v);
          ok_v     := ok_v or (hit_v(i) = '1' and legal_v);
        end loop;
        decoded.ok     <= '1' when ok_v else '0';
        decoded.hit    <= hit_v;
        decoded.merged <= merged_v;
        decoded.bytes  <= bytes_v;
      end if;
    end if;
  end process write_decode;

  -- The register file: a legal decoded write executed, the w1c bits, the interrupt.
  reg_file : process (clk) is
    variable clear_v : reg_words_t;  -- w1c bits cleared by the write
  begin
    if rising_edge(clk) then
      pulses  <= (others => ZERO_c);
      written <= (others => '0');
      clear_v := (others => ZERO_c);
      if decoded_valid = '1' and decoded.ok = '1' then
        for i in REGS_c'range loop
          if decoded.hit(i) = '1' then
            if REGS_c(i).acc = access_w1c then
              clear_v(i) := decoded.merged;
            elsif REGS_c(i).acc = access_rw or (decoded.bytes and REGS_c(i).mask) /= ZERO_c then
              -- rw, or wo with a strobed byte holding a defined bit
              held(i)   <= decoded.merged and stored(REGS_c(i));
              pulses(i) <= decoded.merged and REGS_c(i).pulse;
              if REGS_c(i).acc = access_wo then
                written(i) <= '1';
              end if;
            end if;
          end if;
        end loop;
      end if;
      -- w1c bits: a set pulse in the clock of a clearing write wins
      for i in REGS_c'range loop
        if REGS_c(i).acc = access_w1c then
          held(i) <= ((held(i) and not clear_v(i)) or w1c_set(i)) and stored(REGS_c(i));
        end if;
      end loop;
      if (held(REG_IRQ_STATUS_IDX_c) and held(REG_IRQ_ENABLE_IDX_c)) /= ZERO_c then
        irq_r <= '1';
      else
        irq_r <= '0';
      end if;
      if rst = '1' then
        for i in REGS_c'range loop
          held(i) <= REGS_c(i).reset and stored(REGS_c(i));
        end loop;
        pulses  <= (others => ZERO_c);
        written <= (others => '0');
        irq_r   <= '0';
      end if;
    end if;
  end process reg_file;

  -- AR handshake, register read multiplexer, memory forwarding.
  rd : process (clk) is
    variable addr_v  : natural;
    variable index_v : natural;  -- the word address below MEM_BASE_c
    variable word_v  : word_t;
    variable known_v : boolean;
  begin
    if rising_edge(clk) then
      mem_en_r    <= '0';
      mem_pipe    <= std_logic_vector(shift_left(unsigned(mem_pipe), 1));
      mem_pipe(0) <= mem_en_r;
      if rvalid_r = '1' and s_axil_rready = '1' then
        rvalid_r <= '0';
        ar_busy  <= '0';
      end if;
      if s_axil_arvalid = '1' and ar_busy = '0' then
        ar_busy <= '1';
        addr_v    := to_integer(unsigned(s_axil_araddr));
        index_v    := to_integer(unsigned(s_axil_araddr(LOW_BITS_c - 1 downto 2)));
        if s_axil_araddr(1 downto 0) /= "00" then
          rdata_r  <= ZERO_c;
          rresp_r  <= SLVERR_c;
          rvalid_r <= '1';
        elsif addr_v >= MEM_BASE_c then
          mem_en_r <= '1';
          mem_addr <= std_logic_vector(to_unsigned(addr_v - MEM_BASE_c, ADDR_BITS_g));
        else
          -- an AND-OR multiplexer over the readable registers (aligned and below MEM_BASE_c here)
          word_v := ZERO_c;
          known_v := false;
          for i in REGS_c'range loop
            if REGS_c(i).acc /= access_wo then
              word_v := word_v or sel(index_v = REGS_c(i).offset / 4, read_value(REGS_c(i), held(i), live_in(i)));
              known_v := known_v or index_v = REGS_c(i).offset / 4;
            end if;
          end loop;
          rdata_r  <= word_v;
          rvalid_r <= '1';
          if known_v then
            rresp_r <= OKAY_c;
          else
            rresp_r <= SLVERR_c;
          end if;
        end if;
      end if;
      if mem_pipe(mem_pipe'high) = '1' then
        rdata_r  <= mem_rd_data;
        rresp_r  <= OKAY_c;
        rvalid_r <= '1';
      end if;
      if rst = '1' then
        ar_busy  <= '0';
        rvalid_r <= '0';
        mem_en_r <= '0';
        mem_pipe <= (others => '0');
      end if;
    end if;
  end process rd;

  s_axil_awready <= not aw_full;
  s_axil_wready  <= not w_full;
  s_axil_bresp   <= bresp_r;
  s_axil_bvalid  <= bvalid_r;
  s_axil_arready <= not ar_busy;
  s_axil_rdata   <= rdata_r;
  s_axil_rresp   <= rresp_r;
  s_axil_rvalid  <= rvalid_r;

  -- The budget's reset value (SELECT_BUDGET_RESET_c) can exceed a small bank's capacity, which a
  -- write cannot: the output is held at MEM_DEPTH_g - 1 at most.
  budget_clamp : process (clk) is
    constant CAP_c    : natural := MEM_DEPTH_g - 1;
    variable budget_v : unsigned(budget_r'range);
  begin
    if rising_edge(clk) then
      budget_v := unsigned(held(REG_SELECT_IDX_c)(SELECT_BUDGET_MSB_c downto SELECT_BUDGET_LSB_c));
      if CAP_c < 2 ** budget_r'length and budget_v > CAP_c then
        budget_v := to_unsigned(CAP_c, budget_r'length);
      end if;
      budget_r <= std_logic_vector(budget_v);
    end if;
  end process budget_clamp;

  -- outputs (wiring)
  enable        <= held(REG_CTRL_IDX_c)(CTRL_ENABLE_LSB_c);
  soft_reset    <= pulses(REG_CTRL_IDX_c)(CTRL_SOFT_RESET_LSB_c);
  mode_orb      <= '1' when unsigned(held(REG_CTRL_IDX_c)(CTRL_MODE_MSB_c downto CTRL_MODE_LSB_c)) = 0 else
                   '0';
  threshold     <= held(REG_THRESHOLD_IDX_c)(THRESHOLD_THRESHOLD_MSB_c downto THRESHOLD_THRESHOLD_LSB_c);
  threshold_lo  <= held(REG_THRESHOLD_IDX_c)(THRESHOLD_LOW_MSB_c downto THRESHOLD_LOW_LSB_c);
  select_grid   <= '1' when unsigned(held(REG_SELECT_IDX_c)(SELECT_MODE_MSB_c downto SELECT_MODE_LSB_c)) = 1 else
                   '0';
  grid_cols     <= held(REG_SELECT_IDX_c)(SELECT_COLS_MSB_c downto SELECT_COLS_LSB_c);
  grid_rows     <= held(REG_SELECT_IDX_c)(SELECT_ROWS_MSB_c downto SELECT_ROWS_LSB_c);
  budget        <= budget_r;
  irq           <= irq_r;
  release_valid <= written(REG_BANK_RELEASE_IDX_c);
  release_bank  <= held(REG_BANK_RELEASE_IDX_c)(BANK_RELEASE_BANK_MSB_c downto BANK_RELEASE_BANK_LSB_c);
  mem_rd_en     <= mem_en_r;
  mem_rd_addr   <= mem_addr;
  -- the DDR ring
  ring_base          <= held(REG_RING_BASE_IDX_c)(RING_BASE_BASE_MSB_c downto RING_BASE_BASE_LSB_c);
  ring_stride        <= held(REG_RING_STRIDE_IDX_c)(RING_STRIDE_STRIDE_MSB_c downto RING_STRIDE_STRIDE_LSB_c);
  ring_count         <= held(REG_RING_COUNT_IDX_c)(RING_COUNT_COUNT_MSB_c downto RING_COUNT_COUNT_LSB_c);
  ring_release_valid <= written(REG_RING_RELEASE_IDX_c);
  ring_release_index <= held(REG_RING_RELEASE_IDX_c)(RING_RELEASE_INDEX_MSB_c downto RING_RELEASE_INDEX_LSB_c);

end architecture rtl;
