{% extends "as/program.as" %}
{% block init %}
{%- for o in r.zero_outs %}
  {{ o }} = 0
{%- endfor %}
{% endblock %}
{% block body %}
  ; Mech-Vision (.resource > 0) sends the joint or TCP formats 1 and 2 only.
  IF ({{ r.arg(".resource") }} > 0) AND ({{ r.arg(".getpos_type") }} > 2) THEN
{%- for s in r.status_sets %}
    {{ s }} = {{ p.codes.bad_argument }}
{%- endfor %}
    RETURN
  END
  ; .resource = 0: Mech-Viz ({{ r.cmd }}); N > 0: Mech-Vision project N ({{ r.alt_cmd }}).
  .cmd = {{ r.cmd }}
  .ok = {{ r.ok }}
  IF {{ r.arg(".resource") }} > 0 THEN
    .cmd = {{ r.alt_cmd }}
    .ok = {{ r.alt_ok }}
  END
  .kind = {{ p.kind_tcp }}
  IF ({{ r.arg(".getpos_type") }} == 1) OR ({{ r.arg(".getpos_type") }} == 3) THEN
    .kind = {{ p.kind_joints }}
  END
  ; One waypoint per reply: repeat until the server reports all sent. Every reply adds a
  ; waypoint and .k is capped by the storage, so the loop ends.
  .st = 0
  .k = 0
  .more = 1
  WHILE .more == 1 DO
    .more = 0
    CALL mm_tx_begin(.cmd)
    IF .cmd == {{ r.alt_cmd }} THEN
      CALL mm_tx_add({{ r.arg(".resource") }})
    END
    CALL mm_tx_add({{ r.arg(".getpos_type") }})
    CALL mm_xchg(.cmd, .st)
    IF .st == 0 THEN
      .st = mm_fld[2]
    END
    IF .st == .ok THEN
      CALL mm_plan_wp(.cmd,{{ r.arg(".getpos_type") }},.k,{{ r.arg(".vispos_index") }},.more,.st)
    END
  END
  IF .st == .ok THEN
    mm_pos_num = .k
    mm_pos_kind = .kind
    {{ r.arg(".pos_num") }} = .k
  ELSE
    {{ r.arg(".vispos_index") }} = 0
  END
{% endblock %}
