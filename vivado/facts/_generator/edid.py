import subprocess
EST = {35: ['800x600@60','800x600@56','640x480@75','640x480@72','640x480@67','640x480@60','720x400@88','720x400@70'],
       36: ['1280x1024@75','1024x768@75','1024x768@70','1024x768@60','1024x768@87i','832x624@75','800x600@75','800x600@72'],
       37: [None,None,None,None,None,None,None,'1152x870@75']}
def dtd(b):
    pclk = (b[0] | b[1] << 8) * 10  # kHz
    if pclk == 0: return None
    ha = b[2] | (b[4] >> 4) << 8; hb = b[3] | (b[4] & 15) << 8
    va = b[5] | (b[7] >> 4) << 8; vb = b[6] | (b[7] & 15) << 8
    hso = b[8] | ((b[11] >> 6) & 3) << 8; hsw = b[9] | ((b[11] >> 4) & 3) << 8
    vso = (b[10] >> 4) | ((b[11] >> 2) & 3) << 4; vsw = (b[10] & 15) | (b[11] & 3) << 4
    flags = b[17]; interlaced = bool(flags & 0x80)
    htot = ha + hb; vtot = va + vb
    refresh = pclk * 1000 / (htot * vtot)
    pol = None
    if (flags >> 3) & 3 == 3:
        pol = dict(vsync='+' if flags & 4 else '-', hsync='+' if flags & 2 else '-')
    return dict(pixel_clock_mhz=pclk / 1000, h_active=ha, h_blank=hb, h_front_porch=hso, h_sync=hsw, h_total=htot,
                v_active=va, v_blank=vb, v_front_porch=vso, v_sync=vsw, v_total=vtot, interlaced=interlaced,
                refresh_hz=round(refresh, 3), sync=pol)
def desc(b):
    if b[0] or b[1]:
        return dict(type='detailed_timing', timing=dtd(b))
    tag = b[3]
    txt = bytes(b[5:18]).split(b'\n')[0].decode('ascii', 'replace').strip()
    if tag == 0xFC: return dict(type='monitor_name', text=txt)
    if tag == 0xFF: return dict(type='serial', text=txt)
    if tag == 0xFE: return dict(type='text', text=txt)
    if tag == 0xFD: return dict(type='range_limits', v_min_hz=b[5], v_max_hz=b[6], h_min_khz=b[7], h_max_khz=b[8], max_pixel_clock_mhz=b[9] * 10)
    return dict(type='tag_0x%02X' % tag)
def decode(data):
    assert data[:8] == bytes([0, 255, 255, 255, 255, 255, 255, 0])
    r = {}
    m = data[8] << 8 | data[9]
    r['manufacturer_id'] = ''.join(chr(((m >> s) & 31) + 64) for s in (10, 5, 0))
    r['product_code'] = data[10] | data[11] << 8
    r['week_year'] = [data[16], 1990 + data[17]]
    r['edid_version'] = '%d.%d' % (data[18], data[19])
    r['digital_input'] = bool(data[20] & 0x80)
    r['base_checksum_ok'] = sum(data[:128]) % 256 == 0
    est = []
    for byte, names in EST.items():
        for bit in range(8):
            if data[byte] >> bit & 1 and names[bit]: est.append(names[bit])
    r['established_timings'] = est
    st = []
    for i in range(38, 54, 2):
        if data[i] == 1 and data[i + 1] == 1: continue
        x = (data[i] + 31) * 8; ar = data[i + 1] >> 6; rf = (data[i + 1] & 63) + 60
        y = {0: x * 10 // 16, 1: x * 3 // 4, 2: x * 4 // 5, 3: x * 9 // 16}[ar]
        st.append('%dx%d@%d' % (x, y, rf))
    r['standard_timings'] = st
    r['descriptors'] = [desc(data[54 + 18 * k: 72 + 18 * k]) for k in range(4)]
    r['preferred_timing'] = r['descriptors'][0].get('timing')
    r['extension_blocks'] = data[126]
    if data[126] >= 1 and len(data) >= 256:
        e = data[128:256]
        ce = dict(tag=e[0], revision=e[1], checksum_ok=sum(e) % 256 == 0)
        d = e[2]
        ce['underscan'] = bool(e[3] & 0x80); ce['basic_audio'] = bool(e[3] & 0x40); ce['ycbcr444'] = bool(e[3] & 0x20); ce['ycbcr422'] = bool(e[3] & 0x10)
        ce['native_dtd_count'] = e[3] & 15
        i = 4; blocks = []
        while i < d:
            tag = e[i] >> 5; ln = e[i] & 31; payload = list(e[i + 1:i + 1 + ln])
            blk = dict(tag=tag, length=ln)
            if tag == 2: blk['type'] = 'video'; blk['svd'] = [dict(vic=p & 127, native=bool(p & 128)) for p in payload]
            elif tag == 3: blk['type'] = 'vendor_specific'; blk['oui'] = '%02X%02X%02X' % (payload[2], payload[1], payload[0]) if ln >= 3 else None
            elif tag == 1: blk['type'] = 'audio'
            elif tag == 4: blk['type'] = 'speaker'
            else: blk['type'] = 'other'
            blocks.append(blk); i += 1 + ln
        ce['data_blocks'] = blocks
        dtds = []
        j = d
        while j + 18 <= 127 and (e[j] or e[j + 1]):
            dtds.append(dtd(e[j:j + 18])); j += 18
        ce['detailed_timings'] = dtds
        r['cea861_extension'] = ce
    return r
def load(rev, path, repo='/work/.mirror/Digilent+vivado-library/repo'):
    t = subprocess.check_output(['git', '-C', repo, 'show', '%s:%s' % (rev, path)]).decode()
    return bytes(int(l.strip(), 2) for l in t.split() if l.strip())
