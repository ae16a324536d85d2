from common import *

OUTDIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'ip')
HWH_SIDS = ['zhdmi_hwh', 'zpcam_hwh', 'zpeta_hwh', 'ztof_hwh', 'zdma_hwh', 'cam_hwh', 'pynq24_z2_hwh']
TCL_SIDS = ['zhdmi_tcl', 'zpcam_tcl', 'zpeta_tcl', 'ztof_tcl', 'zdma_tcl', 'pynq_z2_tcl', 'pynq_z1_tcl', 'pynq22_logic_tcl']
SIGNAL = 'xilinx.com:signal:'

HWH = {s: load_hwh(s) for s in HWH_SIDS}
TCL = {s: load_tcl(s) for s in TCL_SIDS}

def clean(dep):
    return ipxact._clean(dep) if dep else None

def hwh_instances(modtype):
    out = []
    for sid in HWH_SIDS:
        a, s, mods = HWH[sid]
        for m in mods:
            if m['modtype'] == modtype:
                out.append((sid, a.get('VIVADOVERSION'), m))
    return out

def tcl_instances(name):
    out = []
    for sid in TCL_SIDS:
        cells, cfg, pins = TCL[sid]
        for cell, v in cells.items():
            if v.split(':')[2] == name:
                out.append((sid, cell, v, cfg.get(cell, {}),
                            sorted(set(p for c, p, k in pins if c == cell and k == 'pin')),
                            sorted(set(p for c, p, k in pins if c == cell and k == 'intf_pin'))))
    return out

def add_src(e, sid):
    if sid not in e['source']:
        e['source'].append(sid)

def build(name, xml_id=None, xml=None, pin_filter=None, pin_patterns=None, intf_patterns=None, docs=(), extra_notes=(), model_map=None,
          hwh_value_params=None, observed_sids=None, track_sids=None, slim_config=False):
    vlnv = 'xilinx.com:ip:' + name
    obj = {'vlnv': vlnv, 'versions_seen': {}, 'sources': [], 'documentation': {d: DOCS[d] for d in docs}}
    used = set()
    interfaces, pins, config = {}, {}, {}
    # ---------------- 1. customised-instance IP-XACT (ports with enablement, user params with choices)
    if xml is None and xml_id:
        xml = load_cam_xml(xml_id)
    if xml is not None:
        sid = 'cam_xml_' + xml_id if xml_id else 'uvl_xml'
        used.add(sid)
        ver = None
        cn = xml['parameters'].get('Component_Name', {}).get('value')
        for mm in HWH['cam_hwh'][2]:
            if dict(mm['params']).get('Component_Name') == cn:
                ver = mm['vlnv'].split(':')[-1]
        if ver is None:
            m = re.match(r'.*_v(\d+)_(\d+)(?:_(\d+))?', xml['modelName'] or '')
            ver = '%s.%s' % (m.group(1), m.group(2)) if m else None
        obj['versions_seen'].setdefault(ver or 'unknown (modelName %s)' % xml['modelName'], []).append(
            '%s (Vivado %s, coreRevision %s)' % (sid, xml['xilinxVersion'], xml['coreExtensions']['coreRevision']))
        obj['display_name'] = xml['coreExtensions']['displayName']
        port_if = {}
        for bn, b in xml['busInterfaces'].items():
            if bn.endswith('_tlm') or (b['abstractionType'] or '').endswith('_tlm:1.0'):
                continue
            e = {'mode': b['mode'], 'type': b['abstractionType'], 'bus_type': b['busType'],
                 'bd_kind': 'pin' if (b['busType'] or '').startswith(SIGNAL) else 'intf_pin',
                 'port_maps': {lg: ph for lg, ph in b['portMaps']}}
            if b['enablement']:
                e['when'] = clean(b['enablement']['dependency'])
            e['source'] = [sid]
            interfaces[bn] = e
            for lg, ph in b['portMaps']:
                port_if.setdefault(ph, []).append(bn)
        tcl_used = set(p for x in tcl_instances(name) for p in x[4])
        for pn, p in xml['ports'].items():
            if p.get('direction') is None:
                continue
            if pin_filter and not pin_filter(pn) and pn not in tcl_used:
                continue
            e = {'dir': dirn(p['direction'])}
            if 'left' in p:
                e['width_in_that_instance'] = '[%s:%s]' % (p['left'], p['right'])
                if p.get('left_dependency'):
                    e['msb_expr'] = p['left_dependency']
            en = p.get('enablement')
            if en:
                e['when'] = clean(en['dependency'])
            ifs = [i for i in port_if.get(pn, []) if i in interfaces]
            e['in_interfaces'] = ifs
            e['source'] = [sid]
            pins[pn] = e
        for cn, p in xml['parameters'].items():
            # a choice list of just 'NA' is how the instance file marks a parameter locked in that
            # instance: no list of legal values (Digilent's Zybo Z7-20 design sets such PS7 parameters)
            values = [c['value'] for c in p['choices']] if p.get('choices') else None
            e = {'kind': 'user', 'values': None if values == ['NA'] else values}
            if values == ['NA']:
                e['note'] = "choice list 'NA' in the instance file: locked there, not a list of legal values"
            if p.get('choices') and any(c['text'] for c in p['choices']):
                e['value_labels'] = {c['value']: c['text'] for c in p['choices']}
            for k in ('minimum', 'maximum'):
                if k in p:
                    e[k] = p[k]
            if not slim_config:
                e['display_name'] = p['displayName']
                e['value_in_xml_instance'] = p['value']
            if p.get('enablement') and p['enablement'].get('dependency'):
                e['editable_when'] = clean(p['enablement']['dependency'])
            e['source'] = [sid]
            config[cn] = e
        obj['hdl_model_parameters_in_xml'] = sorted(xml['modelParameters'])
    # ---------------- 2. hardware handoff instances (every port of the customised instance, every CONFIG parameter)
    hinst = []
    for sid, viv, m in hwh_instances(name):
        used.add(sid)
        ver = m['vlnv'].split(':')[-1]
        obj['versions_seen'].setdefault(ver, [])
        tag = '%s (Vivado %s, coreRevision %s)' % (sid, viv, m['corerev'])
        if tag not in obj['versions_seen'][ver]:
            obj['versions_seen'][ver].append(tag)
        names = [k for k, v in m['params']]
        split = names.index('Component_Name') if 'Component_Name' in names else len(names)
        for i, (k, v) in enumerate(m['params']):
            if k in ('EDK_IPTYPE', 'C_BASEADDR', 'C_HIGHADDR', 'Component_Name'):
                continue
            if k not in config:
                config[k] = {'kind': 'model (listed before Component_Name in HWH: HDL/derived parameter, read-only)' if i < split else 'user? (listed after Component_Name in HWH; not in the IP-XACT instance file used here)',
                             'values': None, 'source': []}
            if track_sids is None or sid in track_sids or not config[k]['source']:
                add_src(config[k], sid)
        members = {}
        for b in m['bifs']:
            for lg, ph in b['portmaps']:
                members.setdefault(ph, []).append(b['name'])
        for p in m['ports']:
            pn = p['name']
            if pin_filter and not pin_filter(pn):
                continue
            if pn not in pins and (pn in members or re.match(r'^[SM]\d\d_AXI_', pn)):
                continue   # member of a bus interface (reached via get_bd_intf_pins); not listed individually
            if pn not in pins:
                e = {'dir': p['dir'], 'when': 'unknown (present in at least one HWH instance)', 'source': []}
                if p['left'] is not None:
                    e['width_in_that_instance'] = '[%s:%s]' % (p['left'], p['right'])
                pins[pn] = e
            add_src(pins[pn], sid)
        for b in m['bifs']:
            if b['name'] not in interfaces:
                interfaces[b['name']] = {'mode': {'MASTER': 'master', 'SLAVE': 'slave', 'INITIATOR': 'master', 'TARGET': 'slave'}.get(b['type'], b['type']),
                                         'bus_type': b['vlnv'], 'bd_kind': 'intf_pin', 'when': 'unknown (seen in HWH)', 'source': []}
            if not interfaces[b['name']].get('port_maps') and b['portmaps']:
                interfaces[b['name']]['port_maps'] = {lg: ph for lg, ph in b['portmaps']}
                interfaces[b['name']]['port_maps_from'] = sid
            add_src(interfaces[b['name']], sid)
        hv = {}
        if hwh_value_params is not None:
            P = dict(m['params'])
            hv = {k: P[k] for k in hwh_value_params if k in P}
        hinst.append({'source': sid, 'instance': m['instance'], 'vlnv': m['vlnv'], 'vivado': viv, 'coreRevision': m['corerev'],
                      'ports_present': [p['name'] for p in m['ports'] if p['name'] not in members and not re.match(r'^[SM]\d\d_AXI_', p['name'])
                                        and (not pin_filter or pin_filter(p['name']))],
                      'ports_present_note': 'members of bus interfaces omitted', 'interfaces_present': [b['name'] for b in m['bifs']],
                      'selected_param_values': hv})
    # ---------------- 3. block-design Tcl (pins and CONFIG names actually used)
    tinst = []
    for sid, cell, v, cfg, pl, il in tcl_instances(name):
        used.add(sid)
        if v.count(':') == 3:
            obj['versions_seen'].setdefault(v.split(':')[-1], [])
            t = '%s (create_bd_cell -vlnv %s)' % (sid, v)
            if t not in obj['versions_seen'][v.split(':')[-1]]:
                obj['versions_seen'][v.split(':')[-1]].append(t)
        for k, val in cfg.items():
            if k not in config:
                config[k] = {'kind': 'seen only in set_property CONFIG', 'values': None, 'source': []}
            if track_sids is None or sid in track_sids or not config[k]['source']:
                add_src(config[k], sid)
            if observed_sids is None or sid in observed_sids:
                config[k].setdefault('observed_tcl_values', {})['%s:%s' % (sid, cell)] = val
        for p in pl:
            if pin_filter and not pin_filter(p) and name == 'clk_wiz':
                continue
            if p not in pins:
                pins[p] = {'dir': None, 'when': 'unknown (seen in connect_bd_net only)', 'source': []}
            add_src(pins[p], sid)
        for p in il:
            if p not in interfaces:
                interfaces[p] = {'mode': None, 'bus_type': None, 'bd_kind': 'intf_pin', 'when': 'unknown (seen in connect_bd_intf_net only)', 'source': []}
            add_src(interfaces[p], sid)
        cs = cfg if len(cfg) <= 60 else {'_omitted': '%d CONFIG values; names are in config[*].source' % len(cfg)}
        tinst.append({'source': sid, 'instance': cell, 'vlnv_in_tcl': v, 'config_set': cs, 'pins_connected': pl, 'intf_pins_connected': il})
    for k, e in interfaces.items():
        if not e.get('type') and e.get('bus_type'):
            v, l, n, ver = e['bus_type'].split(':')
            e['type'] = '%s:%s:%s_rtl:%s' % (v, l, n, ver)
            e['type_inferred_from_bus_type'] = True
    for d in (pins, interfaces, config):
        for k, e in d.items():
            e['confirmed'] = bool(e['source'])
    obj['sources'] = [dict(SOURCES[s], id=s) for s in sorted(used)]
    obj['interfaces'] = interfaces
    obj['pins'] = pins
    if pin_patterns:
        obj['pin_patterns'] = pin_patterns
    if intf_patterns:
        obj['interface_patterns'] = intf_patterns
    obj['config'] = config
    if model_map:
        obj['model_param_to_config'] = verify_map(model_map, name)
        bools = {mp: up for mp, (up, desc, fn) in model_map.items() if desc.startswith('true->1')}
        for d in (pins, interfaces):
            for e in d.values():
                w = e.get('when')
                if not w or not w.startswith('('):
                    continue
                t = w
                for mp, up in bools.items():
                    t = re.sub(r'\b%s\s*(?:=|==|>=)\s*1\b' % mp, '%s == true' % up, t)
                    t = re.sub(r'\b%s\s*(?:=|==)\s*0\b' % mp, '%s == false' % up, t)
                    t = re.sub(r'\bnot %s\b' % mp, '%s == false' % up, t)
                    t = re.sub(r'\b%s\b(?!\s*(?:=|==|>=|!=|<|>))' % mp, '%s == true' % up, t)
                if t != w:
                    e['when_config'] = t
    obj['hwh_instances'] = hinst
    obj['tcl_instances'] = tinst
    obj['notes'] = list(extra_notes)
    return obj

def verify_map(mm, name):
    """mm: {model_param: (user_param, transform_description, fn(user_value)->expected model value)}"""
    out = {}
    for mp, (up, desc, fn) in mm.items():
        n_ok, n_bad = 0, []
        for sid, viv, m in hwh_instances(name):
            P = dict(m['params'])
            if mp in P and up in P:
                if str(fn(P[up], P)) == P[mp]:
                    n_ok += 1
                else:
                    n_bad.append('%s:%s %s=%s %s=%s' % (sid, m['instance'], up, P[up], mp, P[mp]))
        out[mp] = {'config': up, 'relation': desc, 'consistent_in_hwh_instances': n_ok, 'inconsistent': n_bad,
                   'status': 'inferred from value correspondence in HWH files (not documented mapping)'}
    return out

b2i = lambda v, P=None: 1 if v == 'true' else 0

def common_bd_note():
    return ('Every port can be named with get_bd_pins, including members of bus interfaces (in_interfaces lists them; e.g. Digilent connects axi_gpio gpio2_io_i and PYNQ connects processing_system7 GPIO_O directly); '
            'bus interfaces are named with get_bd_intf_pins. Member ports of non-signal interfaces that are not listed under pins can be found in interfaces[*].port_maps.')

def write(name, obj):
    dump('%s/xilinx.com_%s.json' % (OUTDIR, name), obj)
    print(name, 'pins', len(obj['pins']), 'intf', len(obj['interfaces']), 'config', len(obj['config']), 'versions', list(obj['versions_seen']))

# ============================================================== v_tc
vtc_map = {
 'C_HAS_AXI4_LITE': ('HAS_AXI4_LITE', 'true->1, false->0', b2i),
 'C_HAS_INTC_IF': ('HAS_INTC_IF', 'true->1, false->0', b2i),
 'C_DETECT_EN': ('enable_detection', 'true->1', b2i),
 'C_GENERATE_EN': ('enable_generation', 'true->1', b2i),
 'C_DET_HSYNC_EN': ('horizontal_sync_detection', 'true->1', b2i),
 'C_DET_VSYNC_EN': ('vertical_sync_detection', 'true->1', b2i),
 'C_DET_HBLANK_EN': ('horizontal_blank_detection', 'true->1', b2i),
 'C_DET_VBLANK_EN': ('vertical_blank_detection', 'true->1', b2i),
 'C_DET_AVIDEO_EN': ('active_video_detection', 'true->1', b2i),
 'C_DET_ACHROMA_EN': ('active_chroma_detection', 'true->1', b2i),
 'C_GEN_HSYNC_EN': ('horizontal_sync_generation', 'true->1', b2i),
 'C_GEN_VSYNC_EN': ('vertical_sync_generation', 'true->1', b2i),
 'C_GEN_HBLANK_EN': ('horizontal_blank_generation', 'true->1', b2i),
 'C_GEN_VBLANK_EN': ('vertical_blank_generation', 'true->1', b2i),
 'C_GEN_AVIDEO_EN': ('active_video_generation', 'true->1', b2i),
 'C_GEN_ACHROMA_EN': ('active_chroma_generation', 'true->1', b2i),
 'C_GEN_AUTO_SWITCH': ('auto_generation_mode', 'true->1', b2i),
 'C_SYNC_EN': ('SYNC_EN', 'true->1', b2i),
 'C_INTERLACE_EN': ('INTERLACE_EN', 'true->1', b2i),
 'C_GEN_HACTIVE_SIZE': ('GEN_HACTIVE_SIZE', 'equal', lambda v, P: v),
 'C_GEN_VACTIVE_SIZE': ('GEN_VACTIVE_SIZE', 'equal', lambda v, P: v),
 'C_GEN_HFRAME_SIZE': ('GEN_HFRAME_SIZE', 'equal', lambda v, P: v),
 'C_MAX_PIXELS': ('max_clocks_per_line', 'equal', lambda v, P: v),
 'C_MAX_LINES': ('max_lines_per_frame', 'equal', lambda v, P: v),
 'C_NUM_FSYNCS': ('frame_syncs', 'equal', lambda v, P: v),
}
o = build('v_tc', 'v_tc', docs=['PG016'], model_map=vtc_map,
          hwh_value_params=['HAS_AXI4_LITE', 'HAS_INTC_IF', 'enable_detection', 'enable_generation', 'auto_generation_mode', 'horizontal_blank_detection', 'vertical_blank_detection', 'VIDEO_MODE', 'GEN_HACTIVE_SIZE', 'GEN_VACTIVE_SIZE', 'max_clocks_per_line', 'C_GEN_VIDEO_FORMAT'],
          extra_notes=[
  'Port existence is controlled by model parameters (C_*); model_param_to_config gives the settable CONFIG name for each (value correspondence checked in every HWH instance).',
  'Without AXI4-Lite (HAS_AXI4_LITE=false): no ctrl interface and no s_axi_aclk, s_axi_aclken, s_axi_aresetn, s_axi_* and no irq (irq is enabled by C_HAS_AXI4_LITE>=1).',
  'gen_clken exists only when enable_generation=true (C_GENERATE_EN=1); det_clken only when enable_detection=true (C_DETECT_EN=1). clk, clken, resetn, sof_state always exist.',
  'vtiming_in (video_timing slave) exists when enable_detection=true, vtiming_out (master) when enable_generation=true. The individual *_in / *_out timing ports additionally depend on the per-signal detection/generation switches (e.g. hblank_in needs horizontal_blank_detection=true).',
  'intc_if[31:0] exists when HAS_INTC_IF=true. fsync_in when (AXI4-Lite and generation) or (no AXI4-Lite, generation and SYNC_EN); fsync_out[frame_syncs-1:0] when generation is enabled.',
  'Digilent 20/HDMI: v_tc_in = detector only (HAS_INTC_IF=false, enable_generation=false, horizontal/vertical_blank_detection=false) fed from v_vid_in_axi4s vtiming_out; v_tc_out = generator only (enable_detection=false) with gen_clken <- v_axi4s_vid_out vtg_ce and clk <- pixel clock. Both keep AXI4-Lite (ctrl at 0x43C10000 / 0x43C20000) and irq.',
  'The Vivado 2022.1/2023.1 HWH instances (v_tc 6.2 rev 4/6) have extra parameters C_ARBITRARY_RES_EN/ARBITRARY_RES_EN and C_VID_PPC/VID_PPC that the Vivado 2021.1 instance file (rev 2) does not have.',
  'resetn is the core (video clock domain) reset, active low; s_axi_aresetn the AXI4-Lite reset. PG016 is the reference for register map and semantics; it was not read for this file.',
  common_bd_note()])
write('v_tc', o)

# ============================================================== v_vid_in_axi4s
o = build('v_vid_in_axi4s', 'v_vid_in_axi4s', docs=['PG043'],
          hwh_value_params=['C_HAS_ASYNC_CLK', 'C_ADDR_WIDTH', 'C_M_AXIS_VIDEO_FORMAT', 'C_NATIVE_COMPONENT_WIDTH', 'C_M_AXIS_VIDEO_DATA_WIDTH', 'C_PIXELS_PER_CLOCK', 'C_VID_NATIVE_DE'],
          extra_notes=[
  'Here the CONFIG names are the C_* names themselves (C_HAS_ASYNC_CLK, C_ADDR_WIDTH, C_M_AXIS_VIDEO_FORMAT, C_NATIVE_COMPONENT_WIDTH, C_M_AXIS_VIDEO_DATA_WIDTH, C_PIXELS_PER_CLOCK, ...). C_COMPONENTS_PER_PIXEL, C_NATIVE_DATA_WIDTH, C_M_AXIS_TDATA_WIDTH, C_M_AXIS_COMPONENT_WIDTH are derived model parameters.',
  'vid_io_in_clk and vid_io_in_reset exist only when C_HAS_ASYNC_CLK=1 (independent clocks); with C_HAS_ASYNC_CLK=0 the video side runs on aclk.',
  'drop_en exists only with C_INCLUDE_PIXEL_DROP=1 and remap_420_en only with C_INCLUDE_PIXEL_REMAP_420=1 (both 0 by default).',
  'C_M_AXIS_VIDEO_FORMAT labels come from the IP-XACT choice list: 2 = RGB, 12 = Mono/Sensor, 0 = YUV 4:2:2 etc. Digilent 20/HDMI (2023.1 HWH) ends up with C_M_AXIS_VIDEO_FORMAT=2 (RGB), 24-bit tdata, although design_1.tcl only sets C_ADDR_WIDTH=12 and C_HAS_ASYNC_CLK=1.',
  'Version skew: the Vivado 2021.1 instance file is v_vid_in_axi4s v4.0 (rev 9); Vivado 2022.1/2023.1 designs (Digilent HWH) use v5.0 (rev 2), which adds parameter C_VID_NATIVE_DE. The port list of v5.0 in the HWH matches v4.0 minus the disabled drop_en/remap_420_en.',
  'vid_io_in interface (xilinx.com:interface:vid_io:1.0 slave) maps ACTIVE_VIDEO/VBLANK/HBLANK/VSYNC/HSYNC/FIELD/DATA to vid_active_video/vid_vblank/vid_hblank/vid_vsync/vid_hsync/vid_field_id/vid_data. vtiming_out (video_timing master) carries vtd_* for a v_tc detector.',
  'overflow/underflow are status outputs; axis_enable is an input (always present in both versions).',
  common_bd_note()])
write('v_vid_in_axi4s', o)

# ============================================================== v_axi4s_vid_out
o = build('v_axi4s_vid_out', 'v_axi4s_vid_out', docs=['PG044'],
          hwh_value_params=['C_HAS_ASYNC_CLK', 'C_VTG_MASTER_SLAVE', 'C_ADDR_WIDTH', 'C_S_AXIS_VIDEO_FORMAT', 'C_NATIVE_COMPONENT_WIDTH', 'C_HYSTERESIS_LEVEL', 'C_SYNC_LOCK_THRESHOLD', 'C_PIXELS_PER_CLOCK'],
          extra_notes=[
  'vid_io_out_clk and vid_io_out_reset exist only when C_HAS_ASYNC_CLK=1 (value label "Independent"; 0 = "Common").',
  'vtg_ce has NO enablement condition in the IP-XACT instance file: it exists for both C_VTG_MASTER_SLAVE values. C_VTG_MASTER_SLAVE value labels from the choice list: 0 = "Slave", 1 = "Master". Digilent 20/HDMI uses 1 (Master) and still connects vtg_ce -> v_tc_out/gen_clken.',
  'Semantics of the timing mode (from PG044 as summarised by third-party pages, not read here): in slave mode the bridge gates the VTC through vtg_ce to lock the timing to the stream; in master mode the VTC runs freely and the bridge follows it. Treat as unconfirmed.',
  'repeat_en exists only with C_INCLUDE_PIXEL_REPEAT=1, remap_420_en only with C_INCLUDE_PIXEL_REMAP_420=1.',
  'fifo_read_level width is C_ADDR_WIDTH+1 bits ([12:0] for C_ADDR_WIDTH=12); status is [31:0]. locked, overflow, underflow, sof_state_out are outputs.',
  'C_ADDR_WIDTH choice values 5/10/11/12/13 are labelled 32/1024/2048/4096/8192 (FIFO depth). C_S_AXIS_VIDEO_FORMAT 2 = RGB.',
  'The Vivado 2022.1/2023.1 HWH instances list the extra parameter C_ARBITRARY_RES_EN/ARBITRARY_RES_EN, not present in the 2021.1 instance file (rev 12).',
  common_bd_note()])
write('v_axi4s_vid_out', o)

# ============================================================== clk_wiz
def cw_filter(pn):
    # instance-specific renamed clock outputs of the 2021.1 instance file are replaced by generic entries below
    return pn not in ('camif_xclk', 'isp_pclk', 'lcd_clk', 'cam_xclk', 'dvi_clk', 'dvi_clk_x5', 'pxl_clk_5x')
cw_map = {
 'C_USE_RESET': ('USE_RESET', 'true->1', b2i),
 'C_RESET_LOW': ('RESET_TYPE', 'ACTIVE_LOW->1, ACTIVE_HIGH->0', lambda v, P: 1 if v == 'ACTIVE_LOW' else 0),
 'C_USE_LOCKED': ('USE_LOCKED', 'true->1', b2i),
 'C_PRIM_SOURCE': ('PRIM_SOURCE', 'equal', lambda v, P: v),
 'C_USE_DYN_RECONFIG': ('USE_DYN_RECONFIG', 'true->1', b2i),
 'C_INTERFACE_SELECTION': ('USE_DYN_RECONFIG', '1 when USE_DYN_RECONFIG=true and INTERFACE_SELECTION=Enable_AXI', lambda v, P: 1 if (v == 'true' and P.get('INTERFACE_SELECTION') == 'Enable_AXI') else 0),
 'C_ENABLE_CLOCK_MONITOR': ('ENABLE_CLOCK_MONITOR', 'true->1', b2i),
 'C_PRIMITIVE': ('PRIMITIVE', 'equal', lambda v, P: v),
 'C_CLKOUT1_REQUESTED_OUT_FREQ': ('CLKOUT1_REQUESTED_OUT_FREQ', 'equal', lambda v, P: v),
}
o = build('clk_wiz', 'clk_wiz', pin_filter=cw_filter, docs=['PG065'], model_map=cw_map,
          hwh_value_params=['PRIM_IN_FREQ', 'PRIM_SOURCE', 'PRIMARY_PORT', 'CLK_OUT1_PORT', 'CLKOUT1_REQUESTED_OUT_FREQ', 'NUM_OUT_CLKS', 'USE_LOCKED', 'USE_RESET', 'RESET_TYPE', 'RESET_PORT', 'USE_DYN_RECONFIG', 'INTERFACE_SELECTION', 'PRIMITIVE', 'CLKOUT1_DRIVES', 'MMCM_DIVCLK_DIVIDE', 'MMCM_CLKFBOUT_MULT_F', 'MMCM_CLKOUT0_DIVIDE_F', 'MMCM_CLKIN1_PERIOD'],
          pin_patterns={
   'clk_outN (N=1..7)': {'dir': 'O', 'name': 'value of CONFIG.CLK_OUTN_PORT (default "clk_outN"; users may rename, e.g. Digilent Pcam video_dynclk uses pxl_clk_5x, Pmod-VGA xci uses CLK_OUT1)',
                         'when': 'CLKOUTN_USED=true (clk_out1 always; NUM_OUT_CLKS counts them)', 'source': ['zpcam_hwh', 'zpcam_tcl', 'zpeta_hwh', 'pynq24_z2_hwh', 'pynq_z2_tcl', 'zvga_xci', 'cam_xml_clk_wiz'], 'confirmed': True},
   'clk_in1': {'dir': 'I', 'name': 'value of CONFIG.PRIMARY_PORT (default "clk_in1")', 'when': 'PRIM_SOURCE is single-ended or Global_buffer/No_buffer; differential sources give clk_in1_p/clk_in1_n (interface CLK_IN1_D) instead',
               'source': ['cam_xml_clk_wiz', 'zpcam_hwh', 'zpeta_hwh', 'pynq24_z2_hwh'], 'confirmed': True},
   'locked': {'dir': 'O', 'name': 'value of CONFIG.LOCKED_PORT (default "locked")', 'when': 'USE_LOCKED=true (absent in Digilent Petalinux clk_wiz_0 with USE_LOCKED=false)', 'source': ['zpcam_hwh', 'zpeta_hwh', 'cam_xml_clk_wiz', 'zvga_xci'], 'confirmed': True},
   'reset / resetn': {'dir': 'I', 'name': 'port is "reset" when RESET_TYPE=ACTIVE_HIGH and "resetn" when RESET_TYPE=ACTIVE_LOW (set CONFIG.RESET_PORT to the same name, as PYNQ does)', 'when': 'USE_RESET=true and no AXI4-Lite DRP interface (C_USE_RESET=1 and not C_INTERFACE_SELECTION); with USE_DYN_RECONFIG=true the AXI reset s_axi_aresetn is used instead (Digilent Pcam video_dynclk has USE_RESET=true but no reset port)',
                       'source': ['cam_xml_clk_wiz', 'pynq24_z2_hwh', 'pynq_z2_tcl', 'zpcam_hwh'], 'confirmed': True},
          },
          extra_notes=[
  'Output and input port NAMES are parameters (CLK_OUT1_PORT..CLK_OUT7_PORT, PRIMARY_PORT, LOCKED_PORT, RESET_PORT). The 2021.1 instance file used here renamed its outputs (camif_xclk, isp_pclk, lcd_clk, cam_xclk); those instance-specific names were removed from "pins" and replaced by pin_patterns.',
  'Defaults seen: USE_LOCKED and USE_RESET default to true (PYNQ base.tcl does not set USE_RESET yet its HWH shows USE_RESET=true; Digilent Pcam sets USE_RESET {false} explicitly; Pmod-VGA xci sets USE_LOCKED false). This is inferred from write_bd_tcl writing only non-default values.',
  'Dynamic reconfiguration: USE_DYN_RECONFIG=true with INTERFACE_SELECTION=Enable_AXI adds the s_axi_lite interface (s_axi_aclk, s_axi_aresetn, s_axi_*) (Digilent Pcam video_dynclk).',
  'MMCM_* / PLL_* CONFIG values (MMCM_CLKFBOUT_MULT_F, MMCM_DIVCLK_DIVIDE, MMCM_CLKOUT0_DIVIDE_F, MMCM_CLKIN1_PERIOD, ...) are computed by the wizard; write_bd_tcl emits them next to the requested frequencies. Setting only PRIM_IN_FREQ / CLKOUTn_REQUESTED_OUT_FREQ lets the wizard recompute them.',
  'PRIM_SOURCE choices in the Zynq-7000 instance file: Single_ended_clock_capable_pin, Differential_clock_capable_pin, Global_buffer, No_buffer. Use Global_buffer or No_buffer when clk_in1 comes from a PS FCLK (already on a BUFG).',
  'CLKOUTn_DRIVES choices: BUFG, BUFH, BUFGCE, BUFHCE, No_buffer.',
  common_bd_note()])
o['pins']['clk_in1']['when'] = 'PRIM_SOURCE is Single_ended_clock_capable_pin, Global_buffer or No_buffer (differential sources use clk_in1_p/clk_in1_n); actual name = CONFIG.PRIMARY_PORT (default clk_in1)'
o['pins']['locked']['when'] = 'USE_LOCKED == true (default true); actual name = CONFIG.LOCKED_PORT (default locked)'
for n in (1, 2, 3):
    o['pins']['clk_out%d' % n]['when'] = 'CLKOUT%d_USED == true%s; actual name = CONFIG.CLK_OUT%d_PORT (default clk_out%d)' % (n, ' (clk_out1 is always used)' if n == 1 else '', n, n)
o['pins']['reset']['when_config'] = 'USE_RESET == true and RESET_TYPE == ACTIVE_HIGH and no AXI4-Lite DRP (USE_DYN_RECONFIG == false or INTERFACE_SELECTION != Enable_AXI)'
o['pins']['resetn']['when_config'] = 'USE_RESET == true and RESET_TYPE == ACTIVE_LOW and no AXI4-Lite DRP'
write('clk_wiz', o)

# ============================================================== proc_sys_reset
o = build('proc_sys_reset', 'proc_sys_reset', docs=['PG164'],
          hwh_value_params=['C_EXT_RESET_HIGH', 'C_AUX_RESET_HIGH', 'C_NUM_PERP_ARESETN', 'C_NUM_INTERCONNECT_ARESETN', 'C_NUM_BUS_RST', 'C_NUM_PERP_RST'],
          extra_notes=[
  'All ports always exist: slowest_sync_clk, ext_reset_in, aux_reset_in, mb_debug_sys_rst, dcm_locked (inputs); mb_reset, bus_struct_reset[C_NUM_BUS_RST-1:0], peripheral_reset[C_NUM_PERP_RST-1:0], interconnect_aresetn[C_NUM_INTERCONNECT_ARESETN-1:0], peripheral_aresetn[C_NUM_PERP_ARESETN-1:0] (outputs).',
  'The four reset outputs are VECTORS ([0:0] by default), not scalars: in a VHDL wrapper they are std_logic_vector(0 downto 0).',
  'C_EXT_RESET_HIGH / C_AUX_RESET_HIGH select the active level of ext_reset_in / aux_reset_in (0 = active low, the value in every observed instance; range 0..1). Digilent 20/HDMI feeds FCLK_RESET0_N (active low) to ext_reset_in and dvi2rgb pLocked to aux_reset_in with C_AUX_RESET_HIGH=0, so the block is held in reset while pLocked=0.',
  'dcm_locked is an active-high input (tie-off value not visible in these sources); unconnected in Digilent 20/HDMI.',
  'RESET_BOARD_INTERFACE / USE_BOARD_FLOW are board-flow parameters.',
  common_bd_note()])
write('proc_sys_reset', o)

# ============================================================== xlconstant
o = build('xlconstant', 'xlconstant', hwh_value_params=['CONST_WIDTH', 'CONST_VAL'],
          extra_notes=['dout[CONST_WIDTH-1:0] is the only port. CONST_WIDTH range 1..4096. CONST_VAL accepts decimal or 0x-hex (Digilent HWH shows 0x1 for a 1-bit constant set via GUI; PYNQ uses plain integers).',
                       'Digilent 20/HDMI subset_converter_reset: xlconstant with defaults (design_1.tcl sets no CONFIG) -> HWH shows CONST_WIDTH=1, CONST_VAL=0x1, i.e. the default constant is 1.'])
write('xlconstant', o)

# ============================================================== xlconcat
o = build('xlconcat', 'xlconcat', pin_filter=lambda pn: not re.fullmatch(r'In(\d+)', pn) or int(pn[2:]) < 32,
          hwh_value_params=['NUM_PORTS', 'dout_width', 'IN0_WIDTH', 'IN1_WIDTH'],
          pin_patterns={'InN (N=0..127)': {'dir': 'I', 'width': '[INN_WIDTH-1:0]', 'when': 'NUM_PORTS > N (NUM_PORTS range 1..128)', 'source': ['cam_xml_xlconcat'], 'confirmed': True,
                                          'note': 'pins In0..In31 are listed explicitly under "pins"; the instance file lists In0..In127 with the same rule'},
                        'dout': {'dir': 'O', 'width': '[dout_width-1:0]', 'when': 'always', 'source': ['cam_xml_xlconcat'], 'confirmed': True}},
          extra_notes=['Port names are capitalised "In0", "In1", ... (not in0); output is "dout".',
                       'IN<N>_WIDTH range 1..4096 (default 1); dout_width is derived (sum of input widths), it is a user parameter in the instance file but computed by the IP.',
                       'In0 is the LSB of dout. Digilent 20/HDMI concatenates 5 interrupts (NUM_PORTS=5) into processing_system7 IRQ_F2P[4:0].'])
write('xlconcat', o)

# ============================================================== axi_interconnect
o = build('axi_interconnect', 'axi_interconnect', docs=['PG059'],
          hwh_value_params=['NUM_SI', 'NUM_MI', 'STRATEGY'],
          pin_patterns={
            'ACLK / ARESETN': {'dir': 'I', 'when': 'always (interconnect clock and reset)', 'source': ['zhdmi_tcl', 'zhdmi_hwh'], 'confirmed': True},
            'SNN_ACLK / SNN_ARESETN (NN = 00..NUM_SI-1)': {'dir': 'I', 'when': 'NN < NUM_SI (NUM_SI range 1..16)', 'source': ['zhdmi_tcl', 'zhdmi_hwh'], 'confirmed': True},
            'MNN_ACLK / MNN_ARESETN (NN = 00..NUM_MI-1)': {'dir': 'I', 'when': 'NN < NUM_MI (NUM_MI range 1..64)', 'source': ['zhdmi_tcl', 'zhdmi_hwh'], 'confirmed': True}},
          intf_patterns={
            'SNN_AXI': {'mode': 'slave', 'type': 'xilinx.com:interface:aximm_rtl:1.0', 'when': 'NN < NUM_SI', 'source': ['zhdmi_tcl', 'zhdmi_hwh'], 'confirmed': True},
            'MNN_AXI': {'mode': 'master', 'type': 'xilinx.com:interface:aximm_rtl:1.0', 'when': 'NN < NUM_MI', 'source': ['zhdmi_tcl', 'zhdmi_hwh'], 'confirmed': True}},
          extra_notes=[
  'axi_interconnect is a hierarchical IP: the Vivado-generated instance XML has no ports, only user parameters (NUM_SI, NUM_MI, STRATEGY, ENABLE_ADVANCED_OPTIONS, XBAR_DATA_WIDTH, SNN_HAS_REGSLICE, SNN_HAS_DATA_FIFO, SNN_ARB_PRIORITY, MNN_HAS_REGSLICE, MNN_HAS_DATA_FIFO, MNN_SECURE, MNN_ISSUANCE, ...). Pins come from connect_bd_net / HWH.',
  'Names are upper case: ACLK, ARESETN, S00_ACLK, S00_ARESETN, M00_ACLK, M00_ARESETN, S00_AXI, M00_AXI (smartconnect uses lower-case aclk/aresetn).',
  'HAS_REGSLICE values: 0 None, 1 Outer, 3 Auto, 4 Outer and Auto (choice labels). Digilent 20/HDMI sets M00/S00/S01_HAS_REGSLICE=4 on the HP0 interconnect.',
  'In the HWH the interconnect itself is listed with its internal sub-cores; per-port entries under "pins" come from the HWH of Digilent designs and are therefore only the configurations used there (NUM_MI up to 5).'])
write('axi_interconnect', o)

# ============================================================== smartconnect
o = build('smartconnect', 'smartconnect', docs=['PG247'],
          hwh_value_params=['NUM_SI', 'NUM_MI', 'NUM_CLKS', 'HAS_ARESETN'],
          pin_patterns={
            'aclk': {'dir': 'I', 'when': 'always', 'source': ['cam_xml_smartconnect', 'ztof_hwh', 'ztof_tcl'], 'confirmed': True},
            'aclkN (N=1..NUM_CLKS-1)': {'dir': 'I', 'when': 'NUM_CLKS > N (NUM_CLKS range 1..8)', 'confirmed': False,
                                        'evidence': 'name aclk1 appears in several public write_bd_tcl files found by full-text search (repositories not identified by the index), not in any source listed here'},
            'aresetn': {'dir': 'I', 'when': 'HAS_ARESETN=1 (range 0..1)', 'source': ['cam_xml_smartconnect', 'ztof_hwh', 'ztof_tcl'], 'confirmed': True}},
          intf_patterns={
            'SNN_AXI': {'mode': 'slave', 'type': 'xilinx.com:interface:aximm_rtl:1.0', 'when': 'NN < NUM_SI (NUM_SI range 1..16)', 'source': ['cam_xml_smartconnect', 'ztof_hwh'], 'confirmed': True},
            'MNN_AXI': {'mode': 'master', 'type': 'xilinx.com:interface:aximm_rtl:1.0', 'when': 'NN < NUM_MI (NUM_MI range 1..256 in the instance file)', 'source': ['cam_xml_smartconnect', 'ztof_hwh'], 'confirmed': True}},
          extra_notes=['Clock/reset pins are lower case (aclk, aresetn), unlike axi_interconnect (ACLK, ARESETN, SNN_ACLK, ...). SmartConnect has no per-interface clock pins; extra clocks are aclk1.. (NUM_CLKS).',
                       'The IP-XACT of a SmartConnect instance (modelName bd_xxxx) is a generated sub-block-design; user parameters are NUM_SI, NUM_MI, NUM_CLKS, HAS_ARESETN, ADVANCED_PROPERTIES.',
                       '*_tlm interfaces of the instance file (SystemC TLM views) are omitted.'])
write('smartconnect', o)

# ============================================================== util_vector_logic (instance file read through the index, facts transcribed)
uvl_xml = {
 'modelName': 'util_vector_logic_v2_0_1_util_vector_logic', 'xilinxVersion': '2020.2', 'coreExtensions': {'displayName': 'Utility Vector Logic', 'coreRevision': '1'},
 'busInterfaces': {},
 'ports': {'Op1': {'direction': 'in', 'left': '3', 'right': '0', 'left_dependency': '(C_SIZE - 1)'},
           'Op2': {'direction': 'in', 'left': '3', 'right': '0', 'left_dependency': '(C_SIZE - 1)',
                   'enablement': {'value': 'false', 'dependency': "(spirit:decode(id('MODELPARAM_VALUE.C_OPERATION')) != 'not')"}},
           'Res': {'direction': 'out', 'left': '3', 'right': '0', 'left_dependency': '(C_SIZE - 1)'}},
 'parameters': {'Component_Name': {'value': 'design_2_util_vector_logic_0_0', 'displayName': None},
                'C_SIZE': {'value': '4', 'displayName': 'C_SIZE'},
                'C_OPERATION': {'value': 'not', 'displayName': 'C_OPERATION', 'choices': [{'value': v, 'text': None} for v in ('and', 'or', 'xor', 'not')]},
                'LOGO_FILE': {'value': 'data/sym_notgate.png', 'displayName': None}},
 'modelParameters': {'C_OPERATION': {}, 'C_SIZE': {}},
}
uvl_xml['parameters'].pop('Component_Name')
o = build('util_vector_logic', None, xml=uvl_xml, hwh_value_params=['C_OPERATION', 'C_SIZE'],
          extra_notes=['Ports: Op1[C_SIZE-1:0], Op2[C_SIZE-1:0] (absent when C_OPERATION=not), Res[C_SIZE-1:0]. Names are capitalised (Op1, Op2, Res).',
                       'C_OPERATION choices: and, or, xor, not (IP-XACT choice list; the packaged default is not known from these sources, PYNQ v2.2 instances that set only C_SIZE are used as AND gates by name). LOGO_FILE is cosmetic (data/sym_andgate.png, data/sym_orgate.png, data/sym_notgate.png seen).',
                       'Corroboration: uvl_xml stub (C_OPERATION=not) declares only Op1 and Res; uvl_stub2 (2-input op) declares Op1, Op2, Res, each [0:0].',
                       'Versions: util_vector_logic 2.0 (HDL library util_vector_logic_v2_0_1) in every source. No AMD product guide exists for this utility IP as far as known (unconfirmed).',
                       'The instance IP-XACT was read through the search index (not mirrored); its facts are transcribed into this generator.'])
o['sources'] = [dict(SOURCES[s], id=s) for s in ('uvl_xml', 'uvl_stub2', 'pynq22_logic_tcl')]
o['pins']['Op2']['source'].append('uvl_stub2')
for p in ('Op1', 'Res'):
    o['pins'][p]['source'].append('uvl_stub2')
o['versions_seen'] = {'2.0': ['uvl_xml (Vivado 2020.2, util_vector_logic_v2_0_1, coreRevision 1)', 'uvl_stub2 (Vivado 2020.1, util_vector_logic_v2_0_1)', 'pynq22_logic_tcl (create_bd_cell -vlnv xilinx.com:ip:util_vector_logic:2.0)']}
write('util_vector_logic', o)

# ============================================================== processing_system7
ps_xml = load_cam_xml('processing_system7')
sig_if = {bn for bn, b in ps_xml['busInterfaces'].items() if (b['busType'] or '').startswith(SIGNAL)}
member = {}
for bn, b in ps_xml['busInterfaces'].items():
    for lg, ph in b['portMaps']:
        member.setdefault(ph, []).append(bn)
def ps_filter(pn):
    ifs = member.get(pn, [])
    return (not ifs) or any(i in sig_if for i in ifs)
o = build('processing_system7', 'processing_system7', pin_filter=ps_filter, docs=['PG082'], observed_sids={'zhdmi_tcl'},
          track_sids={'cam_xml_processing_system7', 'zhdmi_hwh', 'zhdmi_tcl', 'zpcam_tcl', 'pynq_z2_tcl'}, slim_config=True,
          hwh_value_params=['PCW_USE_M_AXI_GP0', 'PCW_USE_S_AXI_HP0', 'PCW_FPGA0_PERIPHERAL_FREQMHZ', 'PCW_FPGA1_PERIPHERAL_FREQMHZ', 'PCW_FPGA2_PERIPHERAL_FREQMHZ', 'PCW_FPGA3_PERIPHERAL_FREQMHZ',
                            'PCW_EN_CLK0_PORT', 'PCW_EN_CLK1_PORT', 'PCW_EN_CLK2_PORT', 'PCW_EN_CLK3_PORT', 'PCW_EN_RST0_PORT', 'PCW_USE_FABRIC_INTERRUPT', 'PCW_IRQ_F2P_INTR', 'PCW_IRQ_F2P_MODE', 'PCW_NUM_F2P_INTR_INPUTS'])
# Digilent Zybo Z7-20 PS7 configuration (design_1.tcl, 20/HDMI)
cells, cfg, pins = TCL['zhdmi_tcl']
zy = cfg['processing_system7_0']
o['zybo_z7_20_values'] = {'source': 'zhdmi_tcl', 'instance': 'processing_system7_0', 'count': len(zy), 'values': zy,
                          'note': 'Every CONFIG.PCW_* that Digilent\'s write_bd_tcl (Vivado 2023.1) emitted for the Zybo Z7-20 HDMI demo, in file order. The project had BOARD_PART digilentinc.com:zybo-z7-20:part0:1.1, so these are board-preset plus design values; write_bd_tcl omits values equal to the IP default. PCW_ACT_*, PCW_CLKn_FREQ and *_MAX_RANGE style entries are computed (actual) values written alongside the requested ones.'}
# cross-check with board preset
p = git_show(R_BRD, C_BRD, 'new/board_files/zybo-z7-20/A.0/preset.xml')
pre = {}
for mm in re.finditer(r'<ip_preset preset_proc_name="ps7_preset">(.*?)</ip_preset>', p, re.S):
    for k, v in re.findall(r'name="CONFIG\.(\w+)"\s+value="([^"]*)"', mm.group(1)):
        pre[k] = v
o['board_preset_crosscheck'] = {
  'source': 'board20 (preset.xml, ip_preset ps7_preset)', 'preset_count': len(pre),
  'same_value': sorted(k for k in pre if k in zy and pre[k] == zy[k]),
  'different_value': {k: {'board_preset': pre[k], 'digilent_design_1_tcl': zy[k]} for k in pre if k in zy and pre[k] != zy[k]},
  'only_in_board_preset': {k: pre[k] for k in pre if k not in zy},
  'only_in_design_1_tcl': sorted(k for k in zy if k not in pre),
  'note': 'Values only in the preset were presumably equal to the IP default and therefore not written by write_bd_tcl (inference). The preset was changed after the demo (vivado-boards commit db3a6a1, 2023-08-26, "Corrected CPU PLL settings").'}
for k in zy:
    if k not in o['config']:
        o['config'][k] = {'kind': 'seen only in set_property CONFIG', 'values': None, 'source': [], 'confirmed': True}
    o['config'][k]['zybo_z7_20_value'] = zy[k]
hw = [x for x in o['hwh_instances'] if x['source'] == 'zhdmi_hwh'][0]
o['digilent_20_hdmi_ps7_summary'] = {
  'source': ['zhdmi_tcl', 'zhdmi_hwh'],
  'FCLK_CLK0': 'requested 100 MHz (PCW_FPGA0_PERIPHERAL_FREQMHZ=100), actual 100.000000: AXI-Lite control clock (M_AXI_GP0_ACLK, VTC s_axi_aclk, axi_dynclk REF_CLK_I)',
  'FCLK_CLK1': 'requested 134 MHz (PCW_FPGA1_PERIPHERAL_FREQMHZ=134), actual PCW_ACT_FPGA1_PERIPHERAL_FREQMHZ=133.333344: AXI-Stream / HP0 clock',
  'FCLK_CLK2': 'requested 200 MHz, actual 200.000000: dvi2rgb RefClk',
  'FCLK_CLK3': 'not enabled (PCW_EN_CLK3_PORT=0 in HWH, FCLK_CLK3 port absent)',
  'FCLK_RESET0_N': 'present (PCW_EN_RST0_PORT=1, default); FCLK_RESET1..3_N absent',
  'interfaces_present_in_hwh': hw['interfaces_present'],
  'pins_present_in_hwh_excluding_axi_members': [x for x in hw['ports_present'] if not re.match(r'^(M_AXI_GP0_|S_AXI_HP0_)(?!ACLK)', x)],
  'IRQ_F2P': 'IRQ_F2P[4:0] from xlconcat (5 inputs); HWH shows PCW_NUM_F2P_INTR_INPUTS=5 although design_1.tcl does not set it (derived from the connected width).',
  'IIC_0': 'PS I2C0 routed to EMIO (PCW_I2C0_PERIPHERAL_ENABLE=1, PCW_EN_EMIO_I2C0=1) and made external as hdmi_out_ddc (HDMI TX DDC pins G17/G18).',
  'USBIND_0': 'USB0 enabled on MIO 28-39 with reset on MIO 46, so the USBIND_0 interface (USB0_PORT_INDCTL, USB0_VBUS_PWRSELECT, USB0_VBUS_PWRFAULT) appears on the PS7 cell.',
  'MIO': 'PCW_MIO_TREE_PERIPHERALS / PCW_MIO_TREE_SIGNALS in zybo_z7_20_values give the full MIO map: QSPI 1-6,8; Enet0 16-27 + MDIO 52-53; USB0 28-39; SD0 40-45 (CD on 47); USB reset 46; UART1 48-49; GPIO 0,7,9-15,50,51.',
}
o['notes'] = [
  'To limit size, pins lists the ports that are not members of AXI/DDR/FIXED_IO/IIC/GPIO/... interfaces, plus any member port that a listed Tcl connects directly (e.g. GPIO_O in PYNQ). All other member ports (e.g. M_AXI_GP0_ARVALID) are listed in interfaces[*].port_maps (logical -> physical) and are normally reached through the interface (get_bd_intf_pins processing_system7_0/M_AXI_GP0).',
  'Enablement uses the user parameters directly: M_AXI_GP0 and M_AXI_GP0_ACLK when PCW_USE_M_AXI_GP0=1; S_AXI_HP0/S_AXI_HP0_ACLK when PCW_USE_S_AXI_HP0=1; FCLK_CLKn when PCW_EN_CLKn_PORT=1 and PCW_USE_CR_FABRIC=1; FCLK_RESETn_N when PCW_EN_RSTn_PORT=1 and PCW_USE_CR_FABRIC=1; IRQ_F2P when PCW_USE_FABRIC_INTERRUPT=1 and PCW_IRQ_F2P_INTR=1 (width PCW_NUM_F2P_INTR_INPUTS, 1..16, derived); DDR when PCW_EN_DDR=1; IIC_0 when PCW_EN_EMIO_I2C0=1; FIXED_IO always.',
  'PCW_IRQ_F2P_MODE choices DIRECT / REVERSE (editable when PCW_IRQ_F2P_INTR=1). PCW_FPGAn_PERIPHERAL_FREQMHZ are requested frequencies; the PS clock generator rounds them (see PCW_ACT_FPGAn_PERIPHERAL_FREQMHZ).',
  'A build without board files must reproduce zybo_z7_20_values (DDR part MT41K256M16 RE-125 and timing, UART1 on MIO 48-49, Enet0 RGMII on MIO 16-27 with MDIO on 52-53, SD0, USB0 with reset on MIO 46, QSPI, bank voltages LVCMOS 3.3V / 1.8V, 33.333333 MHz PS crystal).',
  'To keep the file small, config[*].source for this IP lists at most the IP-XACT instance file, the 20/HDMI HWH and Tcl, the 20/Pcam-5C Tcl and PYNQ Z2 Tcl (the other HWH files list the same names), and display names / instance values of the unrelated 2021.1 board are omitted.',
  'HWH lists about 876 PCW_* parameters for the 20/HDMI PS7; config here holds the IP-XACT user parameters of the 2021.1 instance file (with choices/ranges), plus every name Digilent sets.',
  common_bd_note()]
o['config_name_count'] = len(o['config'])
write('processing_system7', o)
