{% extends "as/program.as" %}
{% block body %}
  .st = 0
  .i = {{ r.arg(".index") }}
  IF (.i < 1) OR (.i > mm_pos_num) OR (.i <> INT(.i)) THEN
    .st = {{ p.codes.bad_serial }}
  ELSE
    IF mm_pos_kind <> {{ p.kind_joints }} THEN
      .st = {{ p.codes.wrong_data_kind }}
    ELSE
      POINT {{ r.arg(".#targetpos") }} = #PPOINT(vis_pos_j1[.i], vis_pos_j2[.i], vis_pos_j3[.i], vis_pos_j4[.i], vis_pos_j5[.i], vis_pos_j6[.i])
      {{ r.arg(".label") }} = mm_pos_label[.i]
      {{ r.arg(".speed") }} = vis_pos_spd[.i]
    END
  END
{% endblock %}
