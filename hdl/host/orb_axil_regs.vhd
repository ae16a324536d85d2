-- SPDX-License-Identifier: MIT
-- orb_axil_regs: the accelerator's AXI4-Lite register bank (map in orb_regs_pkg, generated from
-- golden_model/data/regmap.json; table and bus rules in docs/registers.md, design in
-- docs/axil-regs.md). It reads back the configuration generics, drives the control outputs
-- (enable, a one-clock soft_reset pulse, mode_orb, the FAST threshold, which the detector
-- applies from the next frame on), shows the status inputs of the other blocks, keeps the
-- interrupt enable and W1C status bits (set by frame_done_pulse and error_pulse; irq is the
-- registered OR(status AND enable)) and pulses release_valid with release_bank when the CPU
-- writes BANK_RELEASE. One transaction per channel at a time: AW and W are each held in a
-- one-entry buffer (awready/wready low while it is full) and may come in any order and with
-- any delay; the write is executed once both are there and no B response is pending; arready is
-- low from an AR handshake until its R handshake. A register read answers on R one clock after
-- the AR handshake. Memory port contract: every 32-bit aligned read at MEM_BASE_c or above
-- raises mem_rd_en for one clock with mem_rd_addr = address - MEM_BASE_c (a byte offset, bits
-- 1..0 zero); orb_feat_mem must drive the word on mem_rd_data so that it is valid at the
-- MEM_LATENCY_g-th rising edge after the edge that sampled mem_rd_en = '1' (1: block RAM
-- output, 2: block RAM with output register), where it is taken and returned with OKAY.
-- SLVERR (no state change) answers misaligned or unknown addresses, writes to ro registers and to
-- the memory window, reads of the wo BANK_RELEASE, and rw/wo writes that set a reserved bit or a
-- field above its maximum (CTRL.mode 2 or 3, BANK_RELEASE.bank >= BANKS_c); byte strobes are
-- honoured (merged into the current value before that check). rst resets the control state and
-- every register to its documented reset value.

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_regs_pkg.all;

entity orb_axil_regs is
  generic (
    WIDTH_g       : positive range 64 to 1920    := 640;
    HEIGHT_g      : positive range 48 to 1080    := 480;
    SCALES_g      : positive range 1 to 4        := 1;
    SECTORS_g     : positive range 4 to 16       := 8;    -- sectors per quadrant: 4, 8 or 16
    MEM_DEPTH_g   : positive range 1 to 16777215 := 4096; -- read back only (CFG_MEM.depth)
    MEM_LATENCY_g : positive range 1 to 8        := 2;    -- mem_rd_en to mem_rd_data, clocks
    ADDR_BITS_g   : positive range 18 to 20      := 18
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
    mem_rd_data   : in    std_logic_vector(31 downto 0)
  );
end entity orb_axil_regs;

architecture rtl of orb_axil_regs is

  subtype word_t is std_logic_vector(31 downto 0);

  constant OKAY_c   : std_logic_vector(1 downto 0) := "00";
  constant SLVERR_c : std_logic_vector(1 downto 0) := "10";
  constant ZERO_c   : word_t := (others => '0');

  -- word with bits msb .. lsb set to value
  function put (word : word_t; value : natural; msb, lsb : natural) return word_t is
    variable w : word_t := word;
  begin
    w(msb downto lsb) := std_logic_vector(to_unsigned(value, msb - lsb + 1));
    return w;
  end function put;

  function put (word : word_t; value : std_logic_vector; msb, lsb : natural) return word_t is
    variable w : word_t := word;
  begin
    w(msb downto lsb) := value;
    return w;
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
  function byte_mask (strb : std_logic_vector(3 downto 0)) return word_t is
    variable m : word_t;
  begin
    for i in 0 to 3 loop
      m(8 * i + 7 downto 8 * i) := (others => strb(i));
    end loop;
    return m;
  end function byte_mask;

  constant CFG_SIZE_WORD_c : word_t :=
                                       put(put(ZERO_c, WIDTH_g, CFG_SIZE_WIDTH_MSB_c, CFG_SIZE_WIDTH_LSB_c),
                                            HEIGHT_g, CFG_SIZE_HEIGHT_MSB_c, CFG_SIZE_HEIGHT_LSB_c);
  constant CFG_ORB_WORD_c  : word_t :=
                                       put(put(put(ZERO_c, SCALES_g, CFG_ORB_SCALES_MSB_c, CFG_ORB_SCALES_LSB_c),
                                                SECTORS_g, CFG_ORB_SECTORS_MSB_c, CFG_ORB_SECTORS_LSB_c),
                                            CFG_ORB_BANKS_RESET_c, CFG_ORB_BANKS_MSB_c, CFG_ORB_BANKS_LSB_c);
  constant CFG_MEM_WORD_c  : word_t :=
                                       put(put(ZERO_c, MEM_DEPTH_g, CFG_MEM_DEPTH_MSB_c, CFG_MEM_DEPTH_LSB_c),
                                            MEM_LATENCY_g, CFG_MEM_LATENCY_MSB_c, CFG_MEM_LATENCY_LSB_c);

  subtype mode_t is std_logic_vector(CTRL_MODE_MSB_c - CTRL_MODE_LSB_c downto 0);
  subtype irq_t is std_logic_vector(IRQ_STATUS_ERROR_MSB_c downto IRQ_STATUS_FRAME_DONE_LSB_c);

  -- write channel
  signal aw_full  : std_logic := '0';
  signal aw_addr  : std_logic_vector(ADDR_BITS_g - 1 downto 0) := (others => '0');
  signal w_full   : std_logic := '0';
  signal w_data   : word_t := (others => '0');
  signal w_strb   : std_logic_vector(3 downto 0) := (others => '0');
  signal bvalid_r : std_logic := '0';
  signal bresp_r  : std_logic_vector(1 downto 0) := OKAY_c;

  -- read channel and memory port
  signal ar_busy  : std_logic := '0';
  signal rvalid_r : std_logic := '0';
  signal rresp_r  : std_logic_vector(1 downto 0) := OKAY_c;
  signal rdata_r  : word_t := (others => '0');
  signal mem_en_r : std_logic := '0';
  signal mem_addr : std_logic_vector(ADDR_BITS_g - 1 downto 0) := (others => '0');
  signal mem_pipe : std_logic_vector(MEM_LATENCY_g - 1 downto 0) := (others => '0');

  -- registers
  signal ctrl_enable : std_logic := '0';
  signal ctrl_mode   : mode_t := (others => '0');
  signal thr         : std_logic_vector(THRESHOLD_THRESHOLD_MSB_c downto THRESHOLD_THRESHOLD_LSB_c) :=
        (others => '0');
  signal irq_en      : irq_t := (others => '0');
  signal irq_st      : irq_t := (others => '0');
  signal irq_r       : std_logic := '0';
  signal soft_rst_r  : std_logic := '0';
  signal rel_valid   : std_logic := '0';
  signal rel_bank    : std_logic_vector(release_bank'range) := (others => '0');

  -- register words as read (reserved bits 0, pulse fields 0)
  signal ctrl_word  : word_t;
  signal thr_word   : word_t;
  signal ien_word   : word_t;
  signal ist_word   : word_t;
  signal stat_word  : word_t;
  signal bank0_word : word_t;
  signal bank1_word : word_t;

begin

  assert SECTORS_g = 4 or SECTORS_g = 8 or SECTORS_g = 16
    report "orb_axil_regs: SECTORS_g (sectors per quadrant) must be 4, 8 or 16"
    severity failure;
  assert 2 ** ADDR_BITS_g > MEM_BASE_c
    report "orb_axil_regs: ADDR_BITS_g leaves no feature-memory window above MEM_BASE_c"
    severity failure;
  assert STATUS_BANK_READY_MSB_c - STATUS_BANK_READY_LSB_c + 1 = BANKS_c and BANK_RELEASE_BANK_MAX_c = BANKS_c - 1
    report "orb_axil_regs: orb_regs_pkg's bank fields do not match BANKS_c"
    severity failure;
  assert IRQ_STATUS_FRAME_DONE_LSB_c = IRQ_ENABLE_FRAME_DONE_LSB_c and IRQ_STATUS_ERROR_LSB_c = IRQ_ENABLE_ERROR_LSB_c
         and IRQ_STATUS_FRAME_DONE_LSB_c = 0 and IRQ_STATUS_ERROR_LSB_c = IRQ_STATUS_ERROR_MSB_c
         and IRQ_STATUS_ERROR_LSB_c = 1
    report "orb_axil_regs: IRQ_ENABLE and IRQ_STATUS must hold frame_done at bit 0 and error at bit 1"
    severity failure;

  ctrl_word  <= put(put(ZERO_c, (0 => ctrl_enable), CTRL_ENABLE_MSB_c, CTRL_ENABLE_LSB_c),
                   ctrl_mode, CTRL_MODE_MSB_c, CTRL_MODE_LSB_c);
  thr_word   <= put(ZERO_c, thr, THRESHOLD_THRESHOLD_MSB_c, THRESHOLD_THRESHOLD_LSB_c);
  ien_word   <= put(ZERO_c, irq_en, IRQ_ENABLE_ERROR_MSB_c, IRQ_ENABLE_FRAME_DONE_LSB_c);
  ist_word   <= put(ZERO_c, irq_st, IRQ_STATUS_ERROR_MSB_c, IRQ_STATUS_FRAME_DONE_LSB_c);
  stat_word  <= put(put(put(ZERO_c, bank_ready, STATUS_BANK_READY_MSB_c, STATUS_BANK_READY_LSB_c),
                       (0 => last_bank), STATUS_LAST_BANK_MSB_c, STATUS_LAST_BANK_LSB_c),
                   (0     => overflow), STATUS_OVERFLOW_MSB_c, STATUS_OVERFLOW_LSB_c);
  bank0_word <= put(put(ZERO_c, bank0_count, BANK0_INFO_COUNT_MSB_c, BANK0_INFO_COUNT_LSB_c),
                    bank0_frame, BANK0_INFO_FRAME_MSB_c, BANK0_INFO_FRAME_LSB_c);
  bank1_word <= put(put(ZERO_c, bank1_count, BANK1_INFO_COUNT_MSB_c, BANK1_INFO_COUNT_LSB_c),
                    bank1_frame, BANK1_INFO_FRAME_MSB_c, BANK1_INFO_FRAME_LSB_c);

  -- AW and W buffers, write execution, the writable registers and the interrupt logic.
  wr : process (clk) is
    variable addr   : natural;
    variable bm     : word_t;
    variable cur    : word_t;
    variable merged : word_t;
    variable ok     : boolean;
    variable clr    : irq_t;
  begin
    if rising_edge(clk) then
      soft_rst_r <= '0';
      rel_valid  <= '0';
      clr        := (others => '0');
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
      if aw_full = '1' and w_full = '1' and bvalid_r = '0' then
        aw_full  <= '0';
        w_full   <= '0';
        bvalid_r <= '1';
        addr     := to_integer(unsigned(aw_addr));
        bm       := byte_mask(w_strb);
        ok       := aw_addr(1 downto 0) = "00" and addr < MEM_BASE_c;
        -- if/elsif rather than case: GHDL 2.0's Verilog output drops a case's `others` (latches)
        if addr = REG_CTRL_c then
          cur := ctrl_word;
        elsif addr = REG_THRESHOLD_c then
          cur := thr_word;
        elsif addr = REG_IRQ_ENABLE_c then
          cur := ien_word;
        else
          -- w1c and wo registers merge into zero
          cur := ZERO_c;
        end if;
        merged := (cur and not bm) or (w_data and bm);
        if ok then
          if addr = REG_CTRL_c then
            ok := (merged and not REG_CTRL_MASK_c) = ZERO_c
                  and unsigned(merged(CTRL_MODE_MSB_c downto CTRL_MODE_LSB_c)) <= CTRL_MODE_MAX_c;
            if ok then
              ctrl_enable <= merged(CTRL_ENABLE_LSB_c);
              ctrl_mode   <= merged(CTRL_MODE_MSB_c downto CTRL_MODE_LSB_c);
              soft_rst_r  <= merged(CTRL_SOFT_RESET_LSB_c);
            end if;
          elsif addr = REG_THRESHOLD_c then
            ok := (merged and not REG_THRESHOLD_MASK_c) = ZERO_c;
            if ok then
              thr <= merged(THRESHOLD_THRESHOLD_MSB_c downto THRESHOLD_THRESHOLD_LSB_c);
            end if;
          elsif addr = REG_IRQ_ENABLE_c then
            ok := (merged and not REG_IRQ_ENABLE_MASK_c) = ZERO_c;
            if ok then
              irq_en <= merged(irq_t'range);
            end if;
          elsif addr = REG_IRQ_STATUS_c then
            -- reserved bits ignored
            clr := merged(irq_t'range);
          elsif addr = REG_BANK_RELEASE_c then
            ok := (merged and not REG_BANK_RELEASE_MASK_c) = ZERO_c
                  and unsigned(merged(BANK_RELEASE_BANK_MSB_c downto BANK_RELEASE_BANK_LSB_c))
                  <= BANK_RELEASE_BANK_MAX_c;
            if ok and w_strb(BANK_RELEASE_BANK_LSB_c / 8) = '1' then
              rel_valid <= '1';
              rel_bank  <= merged(BANK_RELEASE_BANK_MSB_c downto BANK_RELEASE_BANK_LSB_c);
            end if;
          else
            -- ro registers and unknown offsets
            ok := false;
          end if;
        end if;
        if ok then
          bresp_r <= OKAY_c;
        else
          bresp_r <= SLVERR_c;
        end if;
      end if;
      -- a pulse in the clock of a clearing write wins
      irq_st <= (irq_st and not clr) or (error_pulse & frame_done_pulse);
      if (irq_st and irq_en) /= (irq_t'range => '0') then
        irq_r <= '1';
      else
        irq_r <= '0';
      end if;
      if rst = '1' then
        aw_full     <= '0';
        w_full      <= '0';
        bvalid_r    <= '0';
        soft_rst_r  <= '0';
        rel_valid   <= '0';
        ctrl_enable <= REG_CTRL_RESET_c(CTRL_ENABLE_LSB_c);
        ctrl_mode   <= REG_CTRL_RESET_c(CTRL_MODE_MSB_c downto CTRL_MODE_LSB_c);
        thr         <= REG_THRESHOLD_RESET_c(thr'range);
        irq_en      <= REG_IRQ_ENABLE_RESET_c(irq_t'range);
        irq_st      <= REG_IRQ_STATUS_RESET_c(irq_t'range);
        irq_r       <= '0';
      end if;
    end if;
  end process wr;

  -- AR handshake, register read mux, memory forwarding.
  rd : process (clk) is
    variable addr  : natural;
    variable rword : word_t;
    variable known : boolean;
  begin
    if rising_edge(clk) then
      mem_en_r <= '0';
      mem_pipe    <= std_logic_vector(shift_left(unsigned(mem_pipe), 1));
      mem_pipe(0) <= mem_en_r;
      if rvalid_r = '1' and s_axil_rready = '1' then
        rvalid_r <= '0';
        ar_busy  <= '0';
      end if;
      if s_axil_arvalid = '1' and ar_busy = '0' then
        ar_busy <= '1';
        addr    := to_integer(unsigned(s_axil_araddr));
        if s_axil_araddr(1 downto 0) /= "00" then
          rdata_r  <= ZERO_c;
          rresp_r  <= SLVERR_c;
          rvalid_r <= '1';
        elsif addr >= MEM_BASE_c then
          mem_en_r <= '1';
          mem_addr <= std_logic_vector(to_unsigned(addr - MEM_BASE_c, ADDR_BITS_g));
        else
          -- an AND-OR multiplexer over the readable registers (BANK_RELEASE is wo)
          rword := sel(addr = REG_ID_c, REG_ID_RESET_c)
                   or sel(addr = REG_VERSION_c, REG_VERSION_RESET_c)
                   or sel(addr = REG_CFG_SIZE_c, CFG_SIZE_WORD_c)
                   or sel(addr = REG_CFG_ORB_c, CFG_ORB_WORD_c)
                   or sel(addr = REG_CFG_MEM_c, CFG_MEM_WORD_c)
                   or sel(addr = REG_CTRL_c, ctrl_word)
                   or sel(addr = REG_THRESHOLD_c, thr_word)
                   or sel(addr = REG_STATUS_c, stat_word)
                   or sel(addr = REG_FRAME_COUNT_c, frame_count)
                   or sel(addr = REG_DROPPED_c, dropped)
                   or sel(addr = REG_PROTO_ERRORS_c, proto_errors)
                   or sel(addr = REG_IRQ_ENABLE_c, ien_word)
                   or sel(addr = REG_IRQ_STATUS_c, ist_word)
                   or sel(addr = REG_BANK0_INFO_c, bank0_word)
                   or sel(addr = REG_BANK1_INFO_c, bank1_word)
                   or sel(addr = REG_OVERRUN_c, overrun)
                   or sel(addr = REG_OVERFLOW_COUNT_c, overflow_count)
                   or sel(addr = REG_DESC_LOST_c, desc_lost)
                   or sel(addr = REG_DISCARDED_c, discarded);
          known := addr = REG_ID_c or addr = REG_VERSION_c or addr = REG_CFG_SIZE_c or addr = REG_CFG_ORB_c
                   or addr = REG_CFG_MEM_c or addr = REG_CTRL_c or addr = REG_THRESHOLD_c
                   or addr = REG_STATUS_c or addr = REG_FRAME_COUNT_c or addr = REG_DROPPED_c
                   or addr = REG_PROTO_ERRORS_c or addr = REG_IRQ_ENABLE_c or addr = REG_IRQ_STATUS_c
                   or addr = REG_BANK0_INFO_c or addr = REG_BANK1_INFO_c or addr = REG_OVERRUN_c
                   or addr = REG_OVERFLOW_COUNT_c or addr = REG_DESC_LOST_c or addr = REG_DISCARDED_c;
          rdata_r  <= rword;
          rvalid_r <= '1';
          if known then
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

  enable        <= ctrl_enable;
  soft_reset    <= soft_rst_r;
  mode_orb      <= '1' when unsigned(ctrl_mode) = 0 else
                   '0';
  threshold     <= thr;
  irq           <= irq_r;
  release_valid <= rel_valid;
  release_bank  <= rel_bank;
  mem_rd_en     <= mem_en_r;
  mem_rd_addr   <= mem_addr;

end architecture rtl;
