import subprocess, json, os, re, sys, zipfile, io
# Regenerates vivado/facts/*.json from local git mirrors (see vivado/facts/README.md). Mirror paths below.
# Run as `python3 gen_xdc.py` (etc.): Python puts the script's folder, this one, first on the path.
import ipxact, bdtcl
from hwh import parse_hwh

M = '/work/.mirror'
R_VL = M + '/Digilent+vivado-library/repo'
R_XDC = M + '/Digilent+digilent-xdc/repo'
R_BRD = M + '/Digilent+vivado-boards/repo'
R_ZHW = M + '/Digilent+Zybo-Z7-HW/repo'
R_PYNQ = M + '/Xilinx+PYNQ/repo'
R_CAM = M + '/bxinquan+zynq_cam_isp_demo/repo'

C_VL_D03 = 'd03d7cbfa7304ac6f3923a90f9f0de83b0181b12'
C_VL_HEAD = 'f4613fff005b098065fd5d619a2b88e55720a423'
C_XDC = '00a3404901f35aa9567b01ecb3f2c233b6efe9f4'
C_BRD = 'd1898bd01f25d4965f9e50659bbdf70365745a06'
C_HDMI = '2e5322a99edbec0ab3ec8a7f3790abdb0cb45d6f'
C_PCAM = '67cced9f8e37f73f4ef0b797046de301b29d17eb'
C_PETA = '89b4a8e5f9f6f1579cb4768a9aeff0f3640093b9'
C_TOF = '067dd9e38c85fa02d53582ce38e87f9ac196b264'
C_DMA = '3d1cfeb56b83dc7f9314aa4e2f0456d9bfc4bf68'
C_VGA = '9d1f7b21d98900770b4448784f9ea61398a91342'
C_PYNQ = '19ed17d4fd4ea71f95a97d30f8ccd0d62b8dbaaa'
C_PYNQ24 = 'd9c752164644ebdbf7f96e4cd7d96661d1276a34'
C_PYNQ22 = '326b05498bf08b0a22ab51ede428f93ec0d48223'
C_CAM = '2c2cbf2d1af04c4f9cf7f5c4624535a6c49ecb9c'
CAM_IP = 'zynq_cam_isp_demo.gen/sources_1/bd/base/ip'

def git_show(repo, rev, path, binary=False):
    out = subprocess.check_output(['git', '-C', repo, 'show', '%s:%s' % (rev, path)])
    return out if binary else out.decode('utf-8', 'replace')

def hwh_from_xsa(repo, rev, path, name):
    z = zipfile.ZipFile(io.BytesIO(git_show(repo, rev, path, binary=True)))
    return z.read(name)

# --------------------------------------------------------------------------
# Source registry.  Every fact in the JSON files refers to one of these ids.
# --------------------------------------------------------------------------
SOURCES = {
 'xdc': dict(repo='Digilent/digilent-xdc', commit=C_XDC, path='Zybo-Z7-Master.xdc', licence='MIT (License.txt)',
             note='file last changed in commit 8f6665ba784023e05b8fb45354a6d392f68a9498 (2017-09-12)'),
 'board20': dict(repo='Digilent/vivado-boards', commit=C_BRD, path='new/board_files/zybo-z7-20/A.0/{board.xml,part0_pins.xml,preset.xml}',
                 licence='MIT (License.txt; also in each XML header)', note='board file_version 1.2; the 20/HDMI demo used board part digilentinc.com:zybo-z7-20:part0:1.1'),
 'vl_d03': dict(repo='Digilent/vivado-library', commit=C_VL_D03, path='ip/dvi2rgb/*, ip/rgb2dvi/*', licence='MIT (License.txt)',
                note='commit pinned by the repo/vivado-library submodule of Digilent/Zybo-Z7-HW branch 20/HDMI/master (2020-07-27)'),
 'vl_head': dict(repo='Digilent/vivado-library', commit=C_VL_HEAD, path='ip/dvi2rgb/*, ip/rgb2dvi/*', licence='MIT (License.txt)',
                 note='master HEAD of the stored snapshot (2024-05-21)'),
 'zhdmi_tcl': dict(repo='Digilent/Zybo-Z7-HW', commit=C_HDMI, path='src/bd/design_1.tcl', branch='20/HDMI/master',
                   tool='write_bd_tcl, Vivado 2023.1 (IP versions omitted from create_bd_cell)', licence='no licence file in the repository'),
 'zhdmi_hwh': dict(repo='Digilent/Zybo-Z7-HW', commit=C_HDMI, path='hw_handoff/design_1_wrapper.xsa -> design_1.hwh', branch='20/HDMI/master',
                   tool='Vivado 2023.1 hardware handoff (lists every port of every customised IP instance, all CONFIG parameters and IP versions)', licence='no licence file in the repository'),
 'zhdmi_xdc': dict(repo='Digilent/Zybo-Z7-HW', commit=C_HDMI, path='src/constraints/Zybo-Z7-Master.xdc', branch='20/HDMI/master', licence='no licence file in the repository'),
 'zpcam_tcl': dict(repo='Digilent/Zybo-Z7-HW', commit=C_PCAM, path='src/bd/system.tcl', branch='20/Pcam-5C/master', tool='write_bd_tcl, Vivado 2023.1'),
 'zpcam_hwh': dict(repo='Digilent/Zybo-Z7-HW', commit=C_PCAM, path='hw_handoff/system_wrapper.xsa -> system.hwh', branch='20/Pcam-5C/master', tool='Vivado 2023.1'),
 'zpeta_tcl': dict(repo='Digilent/Zybo-Z7-HW', commit=C_PETA, path='src/bd/system.tcl', branch='20/Petalinux/master', tool='write_bd_tcl, Vivado 2022.1'),
 'zpeta_hwh': dict(repo='Digilent/Zybo-Z7-HW', commit=C_PETA, path='hw_handoff/system_wrapper.xsa -> system.hwh', branch='20/Petalinux/master', tool='Vivado 2022.1'),
 'ztof_tcl': dict(repo='Digilent/Zybo-Z7-HW', commit=C_TOF, path='src/bd/design_1.tcl', branch='20/Pmod-ToF/master', tool='write_bd_tcl, Vivado 2022.1'),
 'ztof_hwh': dict(repo='Digilent/Zybo-Z7-HW', commit=C_TOF, path='hw_handoff/design_1_wrapper.xsa -> design_1.hwh', branch='20/Pmod-ToF/master', tool='Vivado 2022.1'),
 'zdma_tcl': dict(repo='Digilent/Zybo-Z7-HW', commit=C_DMA, path='src/bd/system.tcl', branch='20/DMA/master', tool='write_bd_tcl, Vivado 2022.1'),
 'zdma_hwh': dict(repo='Digilent/Zybo-Z7-HW', commit=C_DMA, path='hw_handoff/system_wrapper.xsa -> system.hwh', branch='20/DMA/master', tool='Vivado 2022.1'),
 'zvga_xci': dict(repo='Digilent/Zybo-Z7-HW', commit=C_VGA, path='src/ip/clk_wiz_0/clk_wiz_0.xci', branch='20/Pmod-VGA/master', tool='Vivado 2022.1 XCI (IP-XACT)'),
 'pynq_z2_tcl': dict(repo='Xilinx/PYNQ', commit=C_PYNQ, path='boards/Pynq-Z2/base/base.tcl', tool='write_bd_tcl, Vivado 2024.1 (with IP versions)', licence='BSD-3-Clause (LICENSE)'),
 'pynq_z1_tcl': dict(repo='Xilinx/PYNQ', commit=C_PYNQ, path='boards/Pynq-Z1/base/base.tcl', tool='write_bd_tcl, Vivado 2024.1 (with IP versions)', licence='BSD-3-Clause (LICENSE)'),
 'pynq24_z2_hwh': dict(repo='Xilinx/PYNQ', commit=C_PYNQ24, tag='v2.4', path='boards/Pynq-Z2/base/base.hwh', tool='Vivado 2018.3 hardware handoff', licence='BSD-3-Clause (LICENSE)'),
 'pynq22_logic_tcl': dict(repo='Xilinx/PYNQ', commit=C_PYNQ22, tag='v2.2', path='boards/Pynq-Z2/logictools/logictools.tcl', tool='write_bd_tcl, Vivado 2017.4', licence='BSD-3-Clause (LICENSE)'),
 'cam_hwh': dict(repo='bxinquan/zynq_cam_isp_demo', commit=C_CAM, path='zynq_cam_isp_demo.gen/sources_1/bd/base/hw_handoff/base.hwh', tool='Vivado 2021.1', licence='MIT (LICENSE)'),
 'uvl_xml': dict(repo='Quatton/hw-viv', commit='76fbd375696614695226a0739ceb633e354e6dba',
                 path='renshu/renshu.gen/sources_1/bd/design_2/ip/design_2_util_vector_logic_0_0/design_2_util_vector_logic_0_0.xml (+ _stub.v)',
                 tool='Vivado 2020.2 generated IP-XACT of a customised util_vector_logic instance (C_OPERATION=not, C_SIZE=4)', licence='no licence file found',
                 note='read through the search index (read_file), not a local mirror'),
 'uvl_stub2': dict(repo='madorskya/wib_sim', commit='636820edd2b9f8c4a9909eae1359ecb31f8cfd0a',
                   path='wib_zu6cg/wib_zu6cg.srcs/sources_1/bd/design_1/ip/design_1_util_vector_logic_0_1/design_1_util_vector_logic_0_1_stub.v',
                   tool='Vivado 2020.1 synth stub (two-input operation: Op1, Op2, Res)', note='seen through the search index only'),
}
for ipn, inst in [('smartconnect', 'base_axi_smc_0'), ('clk_wiz', 'base_clk_wiz_0_0'), ('xlconstant', 'base_cmos_pwdn_0'),
                  ('processing_system7', 'base_processing_system7_0_0'), ('axi_interconnect', 'base_ps7_0_axi_periph_0'),
                  ('proc_sys_reset', 'base_rst_ps7_0_100M_0'), ('v_axi4s_vid_out', 'base_v_axi4s_vid_out_0_0'),
                  ('v_tc', 'base_v_tc_0_0'), ('v_vid_in_axi4s', 'base_v_vid_in_axi4s_0_0'), ('xlconcat', 'base_xlconcat_0_0')]:
    SOURCES['cam_xml_' + ipn] = dict(repo='bxinquan/zynq_cam_isp_demo', commit=C_CAM, path='%s/%s/%s.xml' % (CAM_IP, inst, inst),
                                     tool='Vivado 2021.1 generated IP-XACT of a customised instance (ports with PORT_ENABLEMENT expressions, bus interfaces, user parameters with choice lists)',
                                     licence='MIT (LICENSE)')
DOCS = {
 'PG016': 'Video Timing Controller LogiCORE IP Product Guide (v_tc v6.2)',
 'PG043': 'Video In to AXI4-Stream LogiCORE IP Product Guide (v_vid_in_axi4s)',
 'PG044': 'AXI4-Stream to Video Out LogiCORE IP Product Guide (v_axi4s_vid_out v4.0; edition seen in the search index: October 4, 2017)',
 'PG065': 'Clocking Wizard LogiCORE IP Product Guide (clk_wiz v6.0)',
 'PG164': 'Processor System Reset Module LogiCORE IP Product Guide (proc_sys_reset v5.0)',
 'PG059': 'AXI Interconnect LogiCORE IP Product Guide (axi_interconnect v2.1)',
 'PG247': 'SmartConnect LogiCORE IP Product Guide (smartconnect v1.0)',
 'PG082': 'Processing System 7 LogiCORE IP Product Guide (processing_system7 v5.5)',
 'DS187': 'Zynq-7000 SoC (Z-7007S, Z-7012S, Z-7014S, Z-7010, Z-7015, Z-7020) Data Sheet: DC and AC Switching Characteristics',
}

def dirn(d):
    return {'in': 'I', 'out': 'O', 'inout': 'IO', 'I': 'I', 'O': 'O', 'IO': 'IO'}.get(d, d)

def load_tcl(sid):
    s = SOURCES[sid]
    repo = {'Digilent/Zybo-Z7-HW': R_ZHW, 'Xilinx/PYNQ': R_PYNQ}[s['repo']]
    return bdtcl.parse_bd_tcl(git_show(repo, s['commit'], s['path']))

def load_hwh(sid):
    s = SOURCES[sid]
    if sid == 'cam_hwh':
        data = git_show(R_CAM, C_CAM, s['path'], binary=True)
    elif sid == 'pynq24_z2_hwh':
        data = git_show(R_PYNQ, C_PYNQ24, s['path'], binary=True)
    else:
        xsa, name = [x.strip() for x in s['path'].split('->')]
        data = hwh_from_xsa(R_ZHW, s['commit'], xsa, name)
    import tempfile
    with tempfile.NamedTemporaryFile(suffix='.hwh') as t:
        t.write(data); t.flush()
        return parse_hwh(t.name)

def load_cam_xml(ipn):
    s = SOURCES['cam_xml_' + ipn]
    return ipxact.parse(git_show(R_CAM, C_CAM, s['path'], binary=True), True)

def dump(path, obj):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    txt = json.dumps(obj, indent=1, sort_keys=False, ensure_ascii=False)
    # put lists of scalars on one line
    def collapse(m):
        inner = m.group(0)
        items = [x.strip() for x in inner[1:-1].split(',\n')]
        return '[' + ', '.join(items) + ']'
    txt = re.sub(r'\[\n(?:\s*(?:"(?:[^"\\]|\\.)*"|-?[0-9.eE+-]+|true|false|null),?\n)+\s*\]', collapse, txt)
    json.loads(txt)
    with open(path, 'w') as f:
        f.write(txt + '\n')
