{% extends "as/program.as" %}
{% block body %}
  .st = 0
  .i = {{ r.arg(".index") }}
  IF (.i < 1) OR (.i > mm_pos_num) OR (.i <> INT(.i)) THEN
    .st = {{ p.codes.bad_serial }}
  ELSE
    IF mm_pos_kind <> {{ p.kind_tcp }} THEN
      .st = {{ p.codes.wrong_data_kind }}
    ELSE
      POINT {{ r.arg(".&targetpos") }} = TRANS(vis_pos_x[.i], vis_pos_y[.i], vis_pos_z[.i], vis_pos_o[.i], vis_pos_a[.i], vis_pos_t[.i])
      {{ r.arg(".label") }} = mm_pos_label[.i]
      {{ r.arg(".speed") }} = vis_pos_spd[.i]
    END
  END
{% endblock %}
