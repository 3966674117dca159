{% extends "as/program.as" %}
{% block body %}
  CALL mm_tx_begin({{ r.cmd }})
{%- for t in r.tx %}
  CALL mm_tx_add({{ t }})
{%- endfor %}
  ; Robot pose: 1 current joints and flange pose, 2 current flange pose, 3 the given joints,
  ; 0 six zeros.
  CASE {{ r.arg(".sendpos_type") }} OF
    VALUE 1:
      CALL mm_tx_here(1)
    VALUE 2:
      CALL mm_tx_here(0)
    VALUE 3:
      CALL mm_tx_jnt({{ r.arg(".#start_vis") }})
    ANY:
      CALL mm_tx_zero(6)
  END
  .st = 0
  CALL mm_xchg({{ r.cmd }}, .st)
  IF .st == 0 THEN
    .st = mm_fld[2]
  END
{% endblock %}
