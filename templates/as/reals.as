.REALS
mm_skt_ok = 0
mm_sock = -1
mm_status = 0
mm_pos_num = 0
mm_pos_kind = 0
mm_do_ok = 0
mm_tx_n = 0
mm_fld_n = 0
.END
