import xml.etree.ElementTree as ET, re
NS = {'spirit': 'http://www.spiritconsortium.org/XMLSchema/SPIRIT/1685-2009', 'xilinx': 'http://www.xilinx.com'}
S = '{%s}' % NS['spirit']; X = '{%s}' % NS['xilinx']
def _t(e, path):
    x = e.find(path, NS)
    return None if x is None else (x.text or '')
def _enab(e, kind):
    # returns (default_bool_text, dependency) or None
    for ie in e.iter(X + 'isEnabled'):
        return dict(value=ie.text, dependency=ie.get(X + 'dependency'), id=ie.get(X + 'id'))
    return None
def _clean(dep):
    if dep is None: return None
    d = re.sub(r"spirit:decode\(\s*id\(\s*'?(?:MODELPARAM_VALUE|PARAM_VALUE)\.([A-Za-z0-9_]+)'?\s*\)\s*\)", r"\1", dep)
    d = re.sub(r"id\(\s*'?(?:MODELPARAM_VALUE|PARAM_VALUE)\.([A-Za-z0-9_]+)'?\s*\)", r"\1", d)
    d = re.sub(r"\s+", " ", d).strip()
    return d
def parse(path_or_text, is_text=False):
    root = ET.fromstring(path_or_text) if is_text else ET.parse(path_or_text).getroot()
    out = dict(vendor=_t(root, 'spirit:vendor'), library=_t(root, 'spirit:library'), name=_t(root, 'spirit:name'), version=_t(root, 'spirit:version'))
    bifs = {}
    bi = root.find('spirit:busInterfaces', NS)
    if bi is not None:
        for b in bi.findall('spirit:busInterface', NS):
            bt = b.find('spirit:busType', NS); at = b.find('spirit:abstractionType', NS)
            vl = lambda e: None if e is None else ':'.join([e.get(S+'vendor'), e.get(S+'library'), e.get(S+'name'), e.get(S+'version')])
            mode = None
            for m in ('master', 'slave', 'mirroredMaster', 'mirroredSlave', 'system', 'mirroredSystem', 'monitor'):
                if b.find('spirit:' + m, NS) is not None: mode = m
            pms = []
            pm = b.find('spirit:portMaps', NS)
            if pm is not None:
                for p in pm.findall('spirit:portMap', NS):
                    pms.append((_t(p, 'spirit:logicalPort/spirit:name'), _t(p, 'spirit:physicalPort/spirit:name')))
            params = {}
            pe = b.find('spirit:parameters', NS)
            if pe is not None:
                for p in pe.findall('spirit:parameter', NS):
                    params[_t(p, 'spirit:name')] = _t(p, 'spirit:value')
            en = None
            ve = b.find('spirit:vendorExtensions', NS)
            if ve is not None: en = _enab(ve, 'BUSIF')
            bifs[b.find('spirit:name', NS).text] = dict(busType=vl(bt), abstractionType=vl(at), mode=mode, portMaps=pms, params=params, enablement=en)
    ports = {}
    for p in root.findall('spirit:model/spirit:ports/spirit:port', NS):
        w = p.find('spirit:wire', NS)
        if w is None:
            ports[p.find('spirit:name', NS).text] = dict(direction=None, note='non-wire port'); continue
        d = dict(direction=_t(w, 'spirit:direction'))
        v = w.find('spirit:vector', NS)
        if v is not None:
            l = v.find('spirit:left', NS); r = v.find('spirit:right', NS)
            d['left'] = l.text; d['right'] = r.text
            if l.get(S+'dependency'): d['left_dependency'] = _clean(l.get(S+'dependency'))
            if r.get(S+'dependency'): d['right_dependency'] = _clean(r.get(S+'dependency'))
        dv = w.find('spirit:driver/spirit:defaultValue', NS)
        if dv is not None: d['driver_default'] = dv.text
        ve = p.find('spirit:vendorExtensions', NS)
        if ve is not None:
            en = _enab(ve, 'PORT')
            if en: d['enablement'] = en
        ports[p.find('spirit:name', NS).text] = d
    choices = {}
    for c in root.findall('spirit:choices/spirit:choice', NS):
        choices[_t(c, 'spirit:name')] = [dict(value=e.text, text=e.get(S+'text')) for e in c.findall('spirit:enumeration', NS)]
    mparams = {}
    for p in root.findall('spirit:model/spirit:modelParameters/spirit:modelParameter', NS):
        val = p.find('spirit:value', NS)
        mparams[_t(p, 'spirit:name')] = dict(value=val.text, dataType=p.get(S+'dataType'), dependency=_clean(val.get(S+'dependency')))
    uparams = {}
    for p in root.findall('spirit:parameters/spirit:parameter', NS):
        val = p.find('spirit:value', NS)
        d = dict(value=val.text, displayName=_t(p, 'spirit:displayName'), format=val.get(S+'format'), resolve=val.get(S+'resolve'))
        cr = val.get(S+'choiceRef')
        if cr: d['choices'] = choices.get(cr)
        for k in ('minimum', 'maximum'):
            if val.get(S+k) is not None: d[k] = val.get(S+k)
        ve = p.find('spirit:vendorExtensions', NS)
        if ve is not None:
            en = _enab(ve, 'PARAM')
            if en: d['enablement'] = en
        uparams[_t(p, 'spirit:name')] = d
    ce = root.find('spirit:vendorExtensions/xilinx:coreExtensions', NS)
    out['coreExtensions'] = None if ce is None else dict(displayName=_t(ce, 'xilinx:displayName'), coreRevision=_t(ce, 'xilinx:coreRevision'), supportedFamilies=None)
    pi = root.find('spirit:vendorExtensions/xilinx:packagingInfo', NS)
    out['xilinxVersion'] = None if pi is None else _t(pi, 'xilinx:xilinxVersion')
    mn = root.find('spirit:model/spirit:views/spirit:view/spirit:modelName', NS)
    out['modelName'] = None if mn is None else mn.text
    out.update(busInterfaces=bifs, ports=ports, modelParameters=mparams, parameters=uparams, choices=choices)
    return out
