from common import *
import edid

OUTDIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'ip')
SIGNAL_BUSES = ('xilinx.com:signal:',)

def norm_when(dep):
    if dep is None:
        return None
    d = dep.strip()
    m = re.fullmatch(r'\$(\w+)', d)
    if m:
        return '%s == true' % m.group(1)
    m = re.fullmatch(r'(?:\(\))+not \(\$(\w+)\)', d)
    if m:
        return '%s == false' % m.group(1)
    return d

def comp(rev, ip):
    return ipxact.parse(git_show(R_VL, rev, 'ip/%s/component.xml' % ip, binary=True), True)

def build(ip, d, sid):
    port_if = {}
    interfaces = {}
    for name, b in d['busInterfaces'].items():
        en = b['enablement']
        e = {'mode': b['mode'], 'type': b['abstractionType'], 'bus_type': b['busType'],
             'port_maps': {lg: ph for lg, ph in b['portMaps']}}
        if b['params']:
            e['bus_parameters'] = b['params']
        if en:
            e['enablement_raw'] = {'default': en['value'], 'dependency': en['dependency']}
            e['when'] = norm_when(en['dependency']) if en['dependency'] else ('never (statically disabled in component.xml)' if en['value'] == 'false' else None)
        e['bd_kind'] = 'pin' if b['busType'].startswith(SIGNAL_BUSES) else 'intf_pin'
        e['source'] = [sid]
        interfaces[name] = e
        for lg, ph in b['portMaps']:
            port_if.setdefault(ph, []).append(name)
    pins = {}
    for name, p in d['ports'].items():
        e = {'dir': dirn(p['direction'])}
        if 'left' in p:
            e['width'] = '[%s:%s]' % (p['left'], p['right'])
        if 'driver_default' in p:
            e['tie_off_default'] = p['driver_default']
        en = p.get('enablement')
        if en:
            e['when'] = norm_when(en['dependency'])
            e['enablement_raw'] = {'default': en['value'], 'dependency': en['dependency']}
        ifs = port_if.get(name, [])
        e['in_interfaces'] = ifs
        e['source'] = [sid]
        pins[name] = e
    config = {}
    for name, p in d['parameters'].items():
        e = {'values': [c['value'] for c in p['choices']] if p.get('choices') else None,
             'default': p['value'], 'display_name': p['displayName'], 'format': p['format']}
        if p.get('choices') and any(c['text'] for c in p['choices']):
            e['value_labels'] = {c['value']: c['text'] for c in p['choices']}
        en = p.get('enablement')
        if en:
            e['editable_when'] = norm_when(en['dependency']) if en['dependency'] else ('always' if en['value'] == 'true' else 'never')
        e['hdl_generic'] = name in d['modelParameters']
        e['source'] = [sid]
        config[name] = e
    return interfaces, pins, config

def diff(a, b):
    out = []
    for k in ('version', 'xilinxVersion'):
        if a[k] != b[k]:
            out.append({'field': k, 'd03d7cb': a[k], 'master': b[k]})
    if a['coreExtensions'] != b['coreExtensions']:
        out.append({'field': 'coreRevision', 'd03d7cb': a['coreExtensions']['coreRevision'], 'master': b['coreExtensions']['coreRevision']})
    for k in ('busInterfaces', 'ports', 'parameters', 'modelParameters', 'choices'):
        for n in sorted(set(a[k]) | set(b[k])):
            if a[k].get(n) != b[k].get(n):
                out.append({'field': '%s.%s' % (k, n), 'd03d7cb': a[k].get(n), 'master': b[k].get(n)})
    return out

def tcl_usage(vlnv_noversion):
    res = []
    for sid in ('zhdmi_tcl', 'zpcam_tcl', 'zpeta_tcl', 'pynq_z2_tcl', 'pynq_z1_tcl'):
        cells, cfg, pins = load_tcl(sid)
        for cell, v in cells.items():
            if v.split(':')[:3] == vlnv_noversion.split(':')[:3]:
                res.append({'source': sid, 'instance': cell, 'vlnv_in_tcl': v, 'config_set': cfg.get(cell, {}),
                            'pins_connected': sorted(set(p for c, p, k in pins if c == cell and k == 'pin')),
                            'intf_pins_connected': sorted(set(p for c, p, k in pins if c == cell and k == 'intf_pin'))})
    return res

def hwh_usage(modtype):
    res = []
    for sid in ('zhdmi_hwh', 'zpcam_hwh', 'zpeta_hwh'):
        a, s, mods = load_hwh(sid)
        for m in mods:
            if m['modtype'] == modtype:
                res.append({'source': sid, 'vivado': a.get('VIVADOVERSION'), 'instance': m['instance'], 'vlnv': m['vlnv'],
                            'coreRevision': m.get('corerev'), 'params': {k: v for k, v in m['params'] if not k.startswith('EDK_')},
                            'ports_present': [p['name'] for p in m['ports']]})
    return res

# ---------------------------------------------------------------- clocking analysis
VCO_MIN, VCO_MAX = 600.0, 1200.0      # MMCME2, -1 speed grade (DS187); see README
PLL_VCO_MIN, PLL_VCO_MAX = 800.0, 1600.0  # PLLE2, -1 (from memory; unconfirmed)

def mmcm_window(k):
    return [round(VCO_MIN / (5 * k), 3), round(VCO_MAX / (5 * k), 3)]

def kclk_table(kmax, choices):
    rows = []
    for k in range(1, kmax + 1):
        rows.append({'kClkRange': k, 'MMCM_CLKFBOUT_MULT_F': 5 * k, 'MMCM_CLKOUT0_DIVIDE_F': k,
                     'CLKIN1_PERIOD_ns': 6.0 * k, 'CLKIN1_nominal_MHz': round(1000.0 / (6.0 * k), 3),
                     'pixel_clock_window_MHz_for_VCO_600_1200': mmcm_window(k),
                     'offered_by_packaged_IP': str(k) in choices})
    return rows

def modes_vs_k(modes, kmax=5):
    out = []
    for name, f, confirmed, src in modes:
        ok = [k for k in range(1, kmax + 1) if VCO_MIN <= f * 5 * k <= VCO_MAX]
        out.append({'mode': name, 'pixel_clock_MHz': f, 'pixel_clock_confirmed': confirmed, 'pixel_clock_source': src,
                    'kClkRange_in_spec': ok, 'in_spec_with_packaged_choices_1_to_3': [k for k in ok if k <= 3],
                    'vco_MHz_by_kClkRange': {str(k): round(f * 5 * k, 3) for k in range(1, kmax + 1)}})
    return out

# ---------------------------------------------------------------- EDID
def edid_facts():
    res = {}
    for f in ('dgl_1080p_cea', 'dgl_1280_1024_cea', 'dgl_720p_cea'):
        path = 'ip/dvi2rgb/src/%s.data' % f
        a = edid.load(C_VL_D03, path); b = edid.load(C_VL_HEAD, path)
        dd = edid.decode(a)
        res[f + '.data'] = {'path': path, 'identical_at_d03d7cb_and_master': a == b, 'bytes': len(a),
                            'format': 'text, one byte per line written as 8 binary digits (read by EEPROM_8b.vhd InitRamFromFile), not hex',
                            'decoded': dd}
    return res

VIC = {1: '640x480p @59.94/60 Hz 4:3 (25.175/25.2 MHz)', 2: '720x480p @59.94/60 Hz 4:3 (27.0/27.027 MHz)',
       4: '1280x720p @59.94/60 Hz 16:9 (74.176/74.25 MHz)', 16: '1920x1080p @59.94/60 Hz 16:9 (148.35/148.5 MHz)'}

def main():
    for ip in ('dvi2rgb', 'rgb2dvi'):
        d0 = comp(C_VL_D03, ip); d1 = comp(C_VL_HEAD, ip)
        vlnv = 'digilentinc.com:ip:' + ip
        interfaces, pins, config = build(ip, d0, 'vl_d03')
        i1, p1, c1 = build(ip, d1, 'vl_head')
        for tgt, other in ((interfaces, i1), (pins, p1), (config, c1)):
            for k, v in other.items():
                if k in tgt:
                    a = {x: y for x, y in tgt[k].items() if x != 'source'}
                    b = {x: y for x, y in v.items() if x != 'source'}
                    if a == b:
                        tgt[k]['source'].append('vl_head')
                    else:
                        tgt[k]['differs_at_master'] = b
                else:
                    v['only_at_master'] = True
                    tgt[k] = v
        tu = tcl_usage(vlnv)
        hu = hwh_usage(ip)
        for h in hu:
            for pn in h['ports_present']:
                if pn in pins and h['source'] not in pins[pn]['source']:
                    pins[pn]['source'].append(h['source'])
        obj = {
         'vlnv': vlnv,
         'versions_seen': {d0['version']: ['vl_d03 (component.xml, coreRevision %s, packaged with Vivado %s)' % (d0['coreExtensions']['coreRevision'], d0['xilinxVersion']),
                                          'vl_head (component.xml, coreRevision %s, packaged with Vivado %s)' % (d1['coreExtensions']['coreRevision'], d1['xilinxVersion'])]},
         'display_name': d0['coreExtensions']['displayName'],
         'sources': [dict(SOURCES[s], id=s) for s in ('vl_d03', 'vl_head', 'zhdmi_tcl', 'zhdmi_hwh', 'zpcam_tcl', 'zpcam_hwh', 'zpeta_tcl', 'zpeta_hwh', 'pynq_z2_tcl')],
         'schema_notes': ['interfaces/pins/config come from component.xml (IP-XACT) at vl_d03; "source" lists every source that agrees; entries that changed at master carry differs_at_master.',
                          'when: condition under which the port / interface exists (from xilinx:isEnabled dependency). tie_off_default: driver default used when the port is left unconnected.',
                          'in_interfaces: bus interfaces the port is a member of. Interfaces are connected with get_bd_intf_pins cell/<interface>; any port (also an interface member) can be named with get_bd_pins cell/<port>. bd_kind=pin marks single-signal interfaces (clock/reset) whose name equals the port name.',
                          'hdl_generic: the parameter is also an HDL generic (modelParameter).'],
         'interfaces': interfaces,
         'pins': pins,
         'config': config,
         'hdl_generics': {k: v for k, v in d0['modelParameters'].items()},
         'component_xml_diff_d03d7cb_vs_master': diff(d0, d1),
         'usage_in_public_block_designs': tu,
         'hwh_instances': hu,
        }
        notes = []
        if ip == 'dvi2rgb':
            choices = [c['value'] for c in d0['parameters']['kClkRange']['choices']]
            vhd = git_show(R_VL, C_VL_D03, 'ip/dvi2rgb/src/TMDS_Clocking.vhd')
            top = git_show(R_VL, C_VL_D03, 'ip/dvi2rgb/src/dvi2rgb.vhd')
            assert 'CLKFBOUT_MULT_F      => real(kClkRange) * 5.0' in vhd and 'CLKIN1_PERIOD        => real(kClkRange) * 6.0' in vhd
            assert 'CLKOUT0_DIVIDE_F     => real(kClkRange) * 1.0' in vhd and 'BUFR_DIVIDE => "5"' in vhd
            obj['kClkRange_semantics'] = {
              'source': ['vl_d03: ip/dvi2rgb/src/TMDS_Clocking.vhd (MMCME2_ADV DVI_ClkGenerator, BUFIO SerialClkBuffer, BUFR PixelClkBuffer)', 'vl_d03: ip/dvi2rgb/src/dvi2rgb.vhd', 'vl_d03: ip/dvi2rgb/component.xml (choice list)'],
              'rtl': 'MMCME2_ADV with DIVCLK_DIVIDE=1, CLKFBOUT_MULT_F=kClkRange*5, CLKOUT0_DIVIDE_F=kClkRange (5x serial clock -> BUFIO), CLKIN1_PERIOD=kClkRange*6.0 ns; PixelClk = BUFR divide-by-5 of the 5x clock. So F_VCO = F_TMDS_clk * 5 * kClkRange, serial clock = 5 * pixel clock.',
              'rtl_comments': {'TMDS_Clocking.vhd generic': 'kClkRange default 1; comment lists >=120MHz=1, >=60MHz=2, >=40MHz=3, >=30MHz=4, >=25MHz=5',
                               'dvi2rgb.vhd generic': 'kClkRange default 2; comment lists >=120MHz=1, >=60MHz=2, >=40MHz=3',
                               'TMDS_Clocking.vhd caveat': 'the MMCM VCO limits (600-1200 MHz quoted for an Artix-7 -1) are not met by one M/D set for all resolutions'},
              'packaged_choice_list': {c['value']: c['text'] for c in d0['parameters']['kClkRange']['choices']},
              'packaged_default': d0['parameters']['kClkRange']['value'],
              'mmcm_vco_range_MHz_assumed': [VCO_MIN, VCO_MAX],
              'mmcm_vco_range_source': 'DS187 (Zynq-7000 data sheet), MMCM_FVCOMIN=600 MHz, MMCM_FVCOMAX=1200 MHz for -1 speed grade; the data sheet itself was not read here: values taken from the brief, the same numbers are quoted in the TMDS_Clocking.vhd comment (for Artix-7 -1) and in a third-party page citing DS187 v1.11 Table 69 (https://megalodon.jp/ref/2016-0909-1710-05/fpga.blog.jp/archives/cat_561498.html)',
              'table': kclk_table(5, choices),
              'dvi2rgb_xdc_note': 'src/dvi2rgb.xdc: the TMDS clock must be constrained in the top-level project; a too-short period there triggers DRC PDRC-34 (MMCM VCO above maximum). dvi2rgb_ooc.xdc uses create_clock -period 6.060 on TMDS_Clk_p (165 MHz) and 5.000 ns on RefClk.',
              'RefClk': 'RefClk must be 200 MHz (IDELAYCTRL reference; dvi2rgb.vhd port comment; master component.xml adds FREQ_HZ=200000000 on the RefClk interface). Digilent 20/HDMI drives it from FCLK_CLK2 = 200 MHz.',
            }
            modes = [('640x480@60 (VESA DMT / CEA VIC 1)', 25.175, False, 'VESA DMT / CEA-861 value from memory'),
                     ('720x480p60 (CEA VIC 2)', 27.0, False, 'CEA-861 value from memory'),
                     ('800x600@60 (VESA DMT)', 40.0, False, 'VESA DMT value from memory'),
                     ('1024x768@60 (VESA DMT)', 65.0, False, 'VESA DMT value from memory'),
                     ('1280x720p60 (EDID detailed timing)', 74.25, True, 'decoded from the shipped EDID detailed timing descriptors'),
                     ('1280x1024@60 (EDID detailed timing)', 108.0, True, 'decoded from the shipped EDID detailed timing descriptors'),
                     ('1280x1024@75 (VESA DMT)', 135.0, False, 'VESA DMT value from memory'),
                     ('1920x1080p60 (EDID detailed timing)', 148.5, True, 'decoded from the shipped EDID detailed timing descriptors')]
            obj['pixel_clock_vs_kClkRange'] = modes_vs_k(modes)
            obj['answer_640x480'] = {
              'question': 'Does the packaged dvi2rgb (kClkRange choices 1..3) admit a 25.175 MHz pixel clock (640x480@60) within the MMCM VCO spec of a -1 XC7Z020?',
              'answer': 'No. VCO = 25.175 * 5 * kClkRange = 125.9 / 251.75 / 377.6 MHz for kClkRange 1/2/3, all below 600 MHz. kClkRange=5 (VCO 629.4 MHz) would be in spec and the RTL comment lists it (>=25MHz=5), but component.xml offers only 1, 2, 3 in its choice list, so CONFIG.kClkRange {5} is expected to be rejected by IP integrator (not tested here, no Vivado). The lowest in-spec window of the packaged IP is kClkRange=3: 40-80 MHz.',
              'confirmed': 'arithmetic from the RTL and choice list is confirmed; the VCO limits are taken from DS187 as quoted (see mmcm_vco_range_source); the rejection of out-of-list values is Vivado behaviour not tested here',
              'consequence': 'All three shipped EDIDs advertise 640x480@60 (established timing) and CEA VIC 1 and VIC 2 (27 MHz), which the packaged dvi2rgb cannot lock to within spec; a source that picks 640x480 will therefore not be decoded reliably. Digilent\'s 20/HDMI demo sets kClkRange=2, i.e. 60-120 MHz (720p at 74.25 MHz works, 1080p60 at 148.5 MHz does not).',
            }
            obj['edid_files'] = edid_facts()
            obj['edid_summary'] = {
              'shipped_files': ['dgl_1080p_cea.data', 'dgl_1280_1024_cea.data', 'dgl_720p_cea.data'],
              'kEdidFileName_default': d0['parameters']['kEdidFileName']['value'],
              'common_to_all_three': {'manufacturer_id': 'DGL', 'edid_version': '1.3', 'established_timings': ['640x480@60', '800x600@60', '1024x768@60', '1280x1024@75'],
                                      'range_limits': 'V 20-240 Hz, H 15-126 kHz, max pixel clock 160 MHz',
                                      'cea861_extension_svds_vic': [16, 4, 1, 2], 'cea861_detailed_timings': ['1920x1080p60 148.5 MHz', '1280x720p60 74.25 MHz', '1280x1024@60 108 MHz']},
              'preferred_timing': {'dgl_1080p_cea.data': '1920x1080 @60 Hz, 148.5 MHz (h 88/44/148 fp/sync/bp, v 4/5/36, +h +v sync)',
                                   'dgl_1280_1024_cea.data': '1280x1024 @60.02 Hz, 108 MHz (h 48/112/248, v 1/3/38, +h +v)',
                                   'dgl_720p_cea.data': '1280x720 @60 Hz, 74.25 MHz (h 110/40/220, v 5/5/20, +h +v)'},
              'native_svd': {'dgl_1080p_cea.data': 16, 'dgl_1280_1024_cea.data': None, 'dgl_720p_cea.data': 4},
              'advertises_640x480_60': 'yes, in all three files: established-timings bit (byte 0x23 bit 5) and CEA SVD VIC 1',
              'vic_meanings': VIC, 'vic_meanings_confirmed': False, 'vic_meanings_source': 'CEA-861 VIC table from memory (not checked against the standard here)',
              'docs_dat_files': 'ip/dvi2rgb/docs/Advantiv_DGL_*_CEA.dat are hex dumps written by EEditZ (2017-09-07). The 720P one is byte-identical to the .data file; the 1080P and 1280_1024 ones differ only in byte 0x83 (CEA flags/native-DTD count) and the extension checksum (byte 0xFF); the .data files (the ones the IP uses) have valid checksums.',
            }
            notes += ['kClkRange summary: F_VCO = F_pixel * 5 * kClkRange (MULT_F = kClkRange*5, CLKIN1_PERIOD = kClkRange*6 ns). With the -1 MMCM VCO range 600-1200 MHz the in-spec pixel-clock windows are 1: 120-240 MHz, 2: 60-120 MHz, 3: 40-80 MHz (packaged choices), and 4: 30-60 MHz, 5: 24-48 MHz (RTL only, not offered by component.xml). 25.175 MHz (640x480@60) is NOT admitted by any packaged choice. See kClkRange_semantics, pixel_clock_vs_kClkRange and answer_640x480.',
                      'EDID: three 256-byte EDIDs ship (dgl_720p_cea.data default, dgl_1080p_cea.data, dgl_1280_1024_cea.data); all advertise 640x480@60 (established timing and CEA VIC 1). See edid_summary and edid_files.',
                      'PixelClk is an output of dvi2rgb (BUFR, or BUFG when kAddBUFG=true); pLocked (PixelClk domain) and aPixelClkLckd (asynchronous) report MMCM lock. Digilent 20/HDMI uses pLocked -> proc_sys_reset aux_reset_in and axi_gpio.',
                      'aRst/pRst exist when kRstActiveHigh=true; aRst_n/pRst_n when false (Digilent 20/HDMI sets kRstActiveHigh=false and drives aRst_n; pRst_n is left unconnected, tie-off 1).',
                      'DDC (IIC master interface SDA_I/O/T, SCL_I/O/T) exists only when kEmulateDDC=true (default true): the IP then answers EDID reads itself from the selected .data file.',
                      'SerialClk output interface exists only when kEnableSerialClkOutput=true.',
                      'TMDS interface type is digilentinc.com:interface:tmds_rtl:1.0 (mode slave here); board interface names hdmi_in / hdmi_in_ddc come from the Digilent board files (TMDS_BOARD_INTERFACE / IIC_BOARD_INTERFACE).']
        else:
            vhd = git_show(R_VL, C_VL_D03, 'ip/rgb2dvi/src/ClockGen.vhd')
            assert 'CLKFBOUT_MULT        => (kClkRange + 1) * 5' in vhd and 'CLKIN1_PERIOD        => real(kClkRange) * 6.25' in vhd
            assert 'CLKFBOUT_MULT_F      => real(kClkRange) * 5.0' in vhd
            choices = [c['value'] for c in d0['parameters']['kClkRange']['choices']]
            pll_rows = []
            for k in range(1, 6):
                lo, hi = PLL_VCO_MIN / ((k + 1) * 5), PLL_VCO_MAX / ((k + 1) * 5)
                pll_rows.append({'kClkRange': k, 'PLL_CLKFBOUT_MULT': (k + 1) * 5, 'PLL_CLKOUT0_DIVIDE': k + 1, 'PLL_CLKOUT1_DIVIDE': (k + 1) * 5,
                                 'CLKIN1_PERIOD_ns': 6.25 * k, 'pixel_clock_window_MHz_for_PLL_VCO_800_1600': [round(lo, 3), round(hi, 3)],
                                 'offered_by_packaged_IP': str(k) in choices})
            obj['kClkRange_semantics'] = {
              'source': ['vl_d03: ip/rgb2dvi/src/ClockGen.vhd', 'vl_d03: ip/rgb2dvi/src/rgb2dvi.vhd', 'vl_d03: ip/rgb2dvi/component.xml'],
              'applies_when': 'kGenerateSerialClk=true only (ClockGen is instantiated only then; kClkRange and kClkPrimitive are greyed out otherwise). With kGenerateSerialClk=false the SerialClk input pin appears and the user supplies the 5x clock (Digilent 20/HDMI: axi_dynclk PXL_CLK_5X_O).',
              'mmcm_variant (kClkPrimitive=MMCM)': 'MMCME2_ADV: CLKFBOUT_MULT_F=kClkRange*5, CLKOUT0_DIVIDE_F=kClkRange (5x -> BUFIO SerialClk), CLKOUT1_DIVIDE=kClkRange*5 (1x), CLKIN1_PERIOD=kClkRange*6.0 ns, BUFR /5 for the pixel clock. Same VCO arithmetic as dvi2rgb.',
              'pll_variant (kClkPrimitive=PLL, the packaged default)': 'PLLE2_ADV: CLKFBOUT_MULT=(kClkRange+1)*5, CLKOUT0_DIVIDE=kClkRange+1 (5x), CLKOUT1_DIVIDE=(kClkRange+1)*5 (1x), CLKIN1_PERIOD=kClkRange*6.25 ns. F_VCO = F_pix * 5 * (kClkRange+1).',
              'packaged_choice_list': {c['value']: c['text'] for c in d0['parameters']['kClkRange']['choices']},
              'packaged_default': d0['parameters']['kClkRange']['value'] + ' (kClkPrimitive default ' + d0['parameters']['kClkPrimitive']['value'] + ')',
              'mmcm_table': kclk_table(5, choices),
              'pll_table': pll_rows,
              'pll_vco_range_MHz_assumed': [PLL_VCO_MIN, PLL_VCO_MAX], 'pll_vco_range_confirmed': False,
              'pll_vco_range_source': 'from memory (DS187 PLL_FVCOMIN/PLL_FVCOMAX for -1); NOT checked against the data sheet',
            }
            obj['answer_640x480'] = {
              'question': 'Can rgb2dvi generate its own serial clock for a 25.175 MHz pixel clock?',
              'answer': 'Not within spec with the packaged choices. MMCM variant: VCO 125.9/251.75/377.6 MHz for kClkRange 1/2/3 (< 600). PLL variant: VCO = 25.175*5*(k+1) = 251.75/377.6/503.5 MHz (< 800, PLL limit unconfirmed). Use kGenerateSerialClk=false and feed SerialClk = 5 x PixelClk (125.875 MHz) from a clock generator (clk_wiz or axi_dynclk), as Digilent\'s 20/HDMI demo does.',
              'confirmed': 'MMCM arithmetic confirmed against RTL; PLL VCO limits unconfirmed'}
            notes += ['Between d03d7cb and master, component.xml of rgb2dvi is unchanged; only src/ClockGen.vhd changed (process PLL_LockLostDetect sensitivity list gains pRst; commit 469c20a "Fix warning Synth 8-614").',
                      'kClkRange summary (only used when kGenerateSerialClk=true): with the MMCM the in-spec pixel-clock windows are 1: 120-240 MHz, 2: 60-120 MHz, 3: 40-80 MHz (VCO 600-1200 MHz); with the default PLL and an assumed 800-1600 MHz PLL VCO: 1: 80-160, 2: 53.3-106.7, 3: 40-80 MHz. See kClkRange_semantics.',
                      'SerialClk is an input pin only when kGenerateSerialClk=false (PORT_ENABLEMENT "()()not ($kGenerateSerialClk)"); it must be 5x PixelClk and phase-related (same MMCM).',
                      'aRst exists when kRstActiveHigh=true (default), aRst_n when false. There is no pRst in rgb2dvi 1.4.',
                      'kD0Swap/kD1Swap/kD2Swap/kClkSwap invert the polarity of a TMDS lane (for boards with swapped P/N routing); the Zybo Z7 demo leaves them false.',
                      'Digilent 20/HDMI: rgb2dvi_1 with kGenerateSerialClk=false, kRstActiveHigh=false; PixelClk <- axi_dynclk PXL_CLK_O, SerialClk <- PXL_CLK_5X_O, aRst_n <- axi_dynclk LOCKED_O.']
        for dd in (interfaces, pins, config):
            for e in dd.values():
                e['confirmed'] = True
        notes.append('PYNQ (Xilinx/PYNQ base.tcl) uses its own copies digilentinc.com:ip:dvi2rgb:1.7 / rgb2dvi:1.2 from boards/ip; those are older forks, not the vivado-library 2.0 / 1.4 used here.')
        obj['notes'] = notes
        dump('%s/digilentinc.com_%s.json' % (OUTDIR, ip), obj)
        print(ip, len(pins), len(interfaces), len(config), 'diffs', len(obj['component_xml_diff_d03d7cb_vs_master']))

main()
