-- SPDX-License-Identifier: MIT
-- orb_regs_types_pkg: the types of the register-file tables of orb_axil_regs (docs/axil-regs.md).
-- orb_regs_pkg, generated from golden_model/data/regmap.json, fills REGS_c and REG_LIMITS_c with
-- these records (only data is generated); orb_axil_regs decodes every register with them.
-- Types only: no logic, no latency.

library ieee;
use ieee.std_logic_1164.all;

package orb_regs_types_pkg is

  -- The register file orb_axil_regs decodes: orb_regs_pkg's REGS_c(REG_<NAME>_IDX_c) describes
  -- register <NAME>: offset, access, defined bits (mask), reset value of its stored bits or, for a ro register, the
  -- constant value of its fields (reset; 0 in live fields), the bits that follow a generic or an
  -- input port, wired by hand in orb_axil_regs (live), and the pulse fields, which read 0 (pulse).
  -- REG_LIMITS_c lists the fields with a minimum or a maximum: a write of a value outside them
  -- answers SLVERR (mask: the field's bits; min, max: the smallest and largest legal values in
  -- place; depth: the largest legal value is MEM_DEPTH_g - 1 instead of max, which orb_axil_regs
  -- puts in place with lsb; a map without such fields gets one entry with mask 0, which never
  -- refuses).
  type reg_access_t is (access_ro, access_rw, access_w1c, access_wo);

  type reg_desc_t is record
    offset : natural;
    acc    : reg_access_t;
    mask   : std_logic_vector(31 downto 0);
    reset  : std_logic_vector(31 downto 0);
    live   : std_logic_vector(31 downto 0);
    pulse  : std_logic_vector(31 downto 0);
  end record reg_desc_t;

  type reg_desc_array_t is array (natural range <>) of reg_desc_t;

  type reg_limit_t is record
    reg   : natural;
    mask  : std_logic_vector(31 downto 0);
    min   : std_logic_vector(31 downto 0);
    max   : std_logic_vector(31 downto 0);
    depth : boolean;
    lsb   : natural;
  end record reg_limit_t;

  type reg_limit_array_t is array (natural range <>) of reg_limit_t;

end package orb_regs_types_pkg;
