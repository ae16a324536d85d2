from common import *

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'zybo_z7_master_xdc.json')
xdc = git_show(R_XDC, C_XDC, 'Zybo-Z7-Master.xdc')

ports = {}
clocks = []
other = []
section = None
z20_sections = []
header = []
for ln, raw in enumerate(xdc.splitlines(), 1):
    line = raw.strip()
    if not line:
        continue
    if ln < 8 and line.startswith('##'):
        header.append(line.lstrip('#').strip())
        continue
    if line.startswith('##') and not line.startswith('##set') and 'get_ports' not in line:
        txt = line.lstrip('#').strip()
        section = txt
        if 'Zybo Z7-20 only' in txt:
            z20_sections.append(txt)
        continue
    body = line.lstrip('#').strip()
    m = re.match(r'set_property\s+-dict\s+\{([^}]*)\}\s*\[get_ports\s+\{\s*([^}]*?)\s*\}\s*\];?\s*(?:#\s*(.*))?$', body)
    if m:
        kv = m.group(1).split()
        props = dict(zip(kv[0::2], kv[1::2]))
        name = m.group(2).strip()
        comment = (m.group(3) or '').strip()
        e = {'pin': props.pop('PACKAGE_PIN'), 'iostandard': props.pop('IOSTANDARD', None)}
        if props:
            e['other_properties'] = props
        cm = re.match(r'(\S+)\s+Sch=(\S+)', comment)
        e['comment'] = comment
        if cm:
            e['fpga_pin_name'] = cm.group(1)
            e['sch'] = cm.group(2)
        e['section'] = section
        e['zybo_z7_20_only'] = bool(section and 'Zybo Z7-20 only' in section)
        e['line'] = ln
        ports[name] = e
        continue
    m = re.match(r'set_property\s+PACKAGE_PIN\s+(\S+)\s+\[get_ports\s+\{([^}]*)\}\];?\s*(?:#\s*(.*))?$', body)
    if m:
        ports[m.group(2).strip()] = {'pin': m.group(1), 'iostandard': None, 'comment': (m.group(3) or '').strip(),
                                     'fpga_pin_name': (m.group(3) or '').strip(), 'section': section,
                                     'zybo_z7_20_only': bool(section and 'Zybo Z7-20 only' in section), 'line': ln}
        continue
    m = re.match(r'create_clock\s+(.*)$', body)
    if m:
        w = bdtcl.tcl_words(m.group(1))
        d = {'line': ln, 'section': section, 'text_words': w}
        for i, x in enumerate(w):
            if x == '-name': d['name'] = w[i + 1]
            if x == '-period': d['period_ns'] = float(w[i + 1])
            if x == '-waveform': d['waveform_ns'] = [float(v) for v in w[i + 1].split()]
            if x.startswith('[get_ports'):
                d['port'] = bdtcl.tcl_words(x[1:-1])[-1].strip()
        del d['text_words']
        clocks.append(d)
        continue
    other.append({'line': ln, 'section': section, 'text': body})

# ---- cross-check 1: Digilent's own uncommented copy in the 20/HDMI demo
hdmi_xdc = git_show(R_ZHW, C_HDMI, 'src/constraints/Zybo-Z7-Master.xdc')
demo = []
for raw in hdmi_xdc.splitlines():
    s = raw.strip()
    if s.startswith('#') or 'PACKAGE_PIN' not in s:
        continue
    m = re.search(r'PACKAGE_PIN\s+(\S+)\s+IOSTANDARD\s+(\S+)\s*\}\s*\[get_ports\s+\{\s*([^}]*?)\s*\}', s)
    sch = re.search(r'Sch=(\S+)', s)
    demo.append({'demo_port': m.group(3), 'pin': m.group(1), 'iostandard': m.group(2), 'sch': sch.group(1) if sch else None})
by_pin = {v['pin']: k for k, v in ports.items()}
for d in demo:
    mp = by_pin.get(d['pin'])
    d['master_port'] = mp
    d['iostandard_matches_master'] = (mp is not None and ports[mp]['iostandard'] == d['iostandard'])

# ---- cross-check 2: board file part0_pins.xml (used by board automation)
pins_xml = git_show(R_BRD, C_BRD, 'new/board_files/zybo-z7-20/A.0/part0_pins.xml')
board = []
for name, iost, loc in re.findall(r'<pin\s+index="\d+"\s+name\s*="([^"]+)"\s+iostandard="([^"]+)"\s+loc="([^"]+)"', pins_xml):
    mp = by_pin.get(loc)
    board.append({'board_pin': name, 'loc': loc, 'iostandard': iost, 'master_port': mp,
                  'iostandard_matches_master': (mp is not None and ports[mp]['iostandard'] == iost)})

mism = [b for b in board if b['master_port'] and not b['iostandard_matches_master']]
nomatch = [b for b in board if not b['master_port']]

out = {
 'what': "Every port listed (commented-out) in Digilent's Zybo Z7 master XDC, with PACKAGE_PIN, IOSTANDARD and the schematic comment; plus the create_clock lines.",
 'source': dict(SOURCES['xdc'], id='xdc'),
 'file_header': header,
 'applies_to': 'Zybo Z7 Rev. B; the header says it is compatible with both Zybo Z7-20 and Zybo Z7-10. Sections marked "(Zybo Z7-20 only)" use bank 13, which exists only on the XC7Z020 (clg400).',
 'zybo_z7_20_only_sections': z20_sections,
 'zybo_z7_20_only_ports': sorted(k for k, v in ports.items() if v['zybo_z7_20_only']),
 'clocks': clocks,
 'sysclk': {'port': 'sysclk', 'pin': ports['sysclk']['pin'], 'iostandard': ports['sysclk']['iostandard'],
            'create_clock': [c for c in clocks if c.get('port') == 'sysclk'][0],
            'frequency_mhz': round(1000.0 / [c for c in clocks if c.get('port') == 'sysclk'][0]['period_ns'], 3)},
 'ports': ports,
 'other_constraints': other,
 'notes': [
  'All lines in the master XDC are commented out; a design uncomments what it uses and renames the get_ports target.',
  'Port names are Digilent\'s suggested names; IOSTANDARD TMDS_33 is used for the HDMI differential pairs (hdmi_rx_*_p/n, hdmi_tx_*_p/n); HPD/SCL/SDA/CEC are LVCMOS33.',
  'The Pcam MIPI section uses HSUL_12 / LVDS_25 and sets INTERNAL_VREF 0.6 on bank 35; it also carries its own create_clock for dphy_hs_clock_clk_p (2.976 ns).',
  'eth_int_pu_b, fan_fb_pu and cam_gpio carry PULLUP true (see other_properties).',
  'The unconnected-pin lines (netic19_*) have no IOSTANDARD.',
 ],
 'crosscheck_digilent_20_hdmi_demo_xdc': {
   'source': dict(SOURCES['zhdmi_xdc'], id='zhdmi_xdc'),
   'what': 'Uncommented copy used by Digilent\'s Zybo Z7-20 HDMI demo, with renamed ports; each pin mapped back to the master-XDC port with the same PACKAGE_PIN.',
   'entries': demo,
   'all_pins_found_in_master': all(d['master_port'] for d in demo),
   'all_iostandards_match': all(d['iostandard_matches_master'] for d in demo),
 },
 'crosscheck_board_file_part0_pins': {
   'source': dict(SOURCES['board20'], id='board20'),
   'what': 'Pins of the Vivado board file (board automation); each mapped to the master-XDC port with the same LOC.',
   'entries': board,
   'locs_not_in_master_xdc': nomatch,
   'iostandard_mismatches': mism,
 },
}
dump(OUT, out)
print('ports', len(ports), 'clocks', clocks, 'z20', len(out['zybo_z7_20_only_ports']), 'demo ok', out['crosscheck_digilent_20_hdmi_demo_xdc']['all_pins_found_in_master'], out['crosscheck_digilent_20_hdmi_demo_xdc']['all_iostandards_match'])
print('board', len(board), 'nomatch', nomatch, 'mism', mism)
print('other', other)
